#pragma once
// The folds that leave a corner of a box (the paper's cube, Sec. 6), as the cube and map
// experiments read them: of the billows a section finds at the corner (folds.hpp), those within
// a cone about its diagonal standing out a real fraction of the largest (split_corner_billows in
// folds.hpp: the others are ripples and waves of the sides' panels), and what they form; their
// counts over corners and drapes.
#include <map>
#include <vector>

#include "woven/analysis/folds.hpp"

namespace woven::analysis {

/// What the folds leaving a corner form, read from one section (the experiments: 0.10 m below
/// the top); a single one "on the diagonal" within kDiagonalToleranceDeg (folds.hpp).
enum class LeavingFolds { NONE, SINGLE_DIAGONAL, SINGLE_OFFSET, MULTIPLE };
/// "none", "single, on the diagonal", "single, off the diagonal", "two or more folds".
const char* structure_name(LeavingFolds s);

/// The billows of a corner that leave it: the folds of split_corner_billows (folds.hpp).
std::vector<Billow> leaving(const std::vector<Billow>& all);

/// The structure of a corner's billows (those leaving it count).
LeavingFolds classify_leaving(const std::vector<Billow>& all);

/// Counts over corners: each structure, and the single billows' angles.
struct CornerCounts {
    std::map<LeavingFolds, int> count;
    int corners = 0, singles = 0;
    double sum_angle_deg = 0, sum_abs_angle_deg = 0;  ///< over the single billows leaving their corners
    /// Adds one corner (all its billows on the section).
    void add(const std::vector<Billow>& all);
};

/// How many of `energies` (J) differ from each other by more than `rel` relative: the distinct
/// drapes among seeds (with a symmetric start and no perturbation every seed gives the same).
int distinct_energies(std::vector<double> energies, double rel = 1e-9);

/// One drape over the box read as a whole: the structure most of its four corners show (ties to
/// the first in LeavingFolds's order), the mean count of billows leaving a corner and the mean
/// |angle| of single ones.
struct CornerSummary {
    LeavingFolds majority = LeavingFolds::NONE;
    double mean_billows = 0, mean_abs_angle = 0;
};
/// `corners`: each corner's billows on the section (four; none read when `has_folds` is false,
/// a drape without a box to analyse).
CornerSummary summarise_corners(bool has_folds, const std::vector<std::vector<Billow>>& corners);

}  // namespace woven::analysis
