// A corner's fold structure (leaving_folds.hpp).
#include "woven/analysis/leaving_folds.hpp"

#include <algorithm>
#include <cmath>

namespace woven::analysis {

const char* structure_name(LeavingFolds s)
{
    switch (s) {
    case LeavingFolds::NONE: return "none";
    case LeavingFolds::SINGLE_DIAGONAL: return "single, on the diagonal";
    case LeavingFolds::SINGLE_OFFSET: return "single, off the diagonal";
    case LeavingFolds::MULTIPLE: return "two or more folds";
    }
    return "";
}

std::vector<Billow> leaving(const std::vector<Billow>& all) { return split_corner_billows(all).folds; }

LeavingFolds classify_leaving(const std::vector<Billow>& all)
{
    const std::vector<Billow> billows = leaving(all);
    if (billows.empty()) return LeavingFolds::NONE;
    if (billows.size() > 1) return LeavingFolds::MULTIPLE;
    return std::abs(billows[0].angle_deg) <= kDiagonalToleranceDeg ? LeavingFolds::SINGLE_DIAGONAL : LeavingFolds::SINGLE_OFFSET;
}

void CornerCounts::add(const std::vector<Billow>& all)
{
    const auto b = leaving(all);
    ++count[classify_leaving(b)];
    ++corners;
    if (b.size() == 1) {
        sum_angle_deg += b[0].angle_deg;
        sum_abs_angle_deg += std::abs(b[0].angle_deg);
        ++singles;
    }
}

int distinct_energies(std::vector<double> energies, double rel)
{
    std::sort(energies.begin(), energies.end());
    int distinct = energies.empty() ? 0 : 1;
    for (std::size_t k = 1; k < energies.size(); ++k)
        if (energies[k] - energies[k - 1] > rel * std::abs(energies[k])) ++distinct;
    return distinct;
}

CornerSummary summarise_corners(bool has_folds, const std::vector<std::vector<Billow>>& corners)
{
    CornerSummary cell;
    std::map<LeavingFolds, int> count;
    int singles = 0;
    if (has_folds)
        for (int k = 0; k < 4; ++k) {
            const auto b = leaving(corners[k]);
            cell.mean_billows += b.size() / 4.0;
            ++count[classify_leaving(b)];
            if (b.size() == 1) {
                cell.mean_abs_angle += std::abs(b[0].angle_deg);
                ++singles;
            }
        }
    if (singles) cell.mean_abs_angle /= singles;
    int best = -1;
    for (const auto& [s, n] : count)
        if (n > best) {
            best = n;
            cell.majority = s;
        }
    return cell;
}

}  // namespace woven::analysis
