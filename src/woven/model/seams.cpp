#include "woven/model/seams.hpp"

#include <algorithm>
#include <cassert>

namespace woven::model {

Local<9> SeamTerm::evaluate(const VecN<27>& x, Derivatives what) const
{
    Local<9> l;
    const Vec3 d = gap(x, c_);
    l.value = 0.5 * k_ * d.squaredNorm();
    if (what == Derivatives::NONE) return l;
    for (int a = 0; a < 9; ++a) l.gradient.segment<3>(3 * a) = k_ * c_[a] * d;
    if (!wants_hessian(what)) return l;
    l.hessian.setZero();
    for (int a = 0; a < 9; ++a)
        for (int b = 0; b < 9; ++b) l.hessian.block<3, 3>(3 * a, 3 * b) = (k_ * c_[a] * c_[b]) * Mat3::Identity();
    return l;
}

std::vector<double> stitch_gaps(const SeamSet& seams, const Positions& x)
{
    std::vector<double> out;
    out.reserve(seams.stitches.size());
    for (const Stitch& s : seams.stitches) {
        Vec3 d = Vec3::Zero();
        for (int i = 0; i < 9; ++i) d += s.c[i] * x[s.ids[i]];
        out.push_back(d.norm());
    }
    return out;
}

void couple_stitches(Stencils& stencils, const std::vector<Stitch>& stitches)
{
    const int n = static_cast<int>(stencils.coupled_begin_.size()) - 1;
    std::vector<std::vector<int>> rows(n);
    for (int p = 0; p < n; ++p) {
        const auto row = stencils.coupled_with(p);
        rows[p].assign(row.begin(), row.end());
    }
    for (const Stitch& s : stitches) {
        for (int a : s.ids)
            for (int b : s.ids) rows[a].push_back(b);
    }
    stencils.coupled_begin_.assign(n + 1, 0);
    for (int p = 0; p < n; ++p) {
        std::sort(rows[p].begin(), rows[p].end());
        rows[p].erase(std::unique(rows[p].begin(), rows[p].end()), rows[p].end());
        stencils.coupled_begin_[p + 1] = stencils.coupled_begin_[p] + static_cast<int>(rows[p].size());
    }
    stencils.coupled_.clear();
    stencils.coupled_.reserve(stencils.coupled_begin_[n]);
    for (const auto& row : rows) stencils.coupled_.insert(stencils.coupled_.end(), row.begin(), row.end());
}

}  // namespace woven::model
