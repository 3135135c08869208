#pragma once
// A Verlet list of the repulsion pairs (Eq. 2, 4): the spatial hash of ClothModel::close_pairs
// is run with the radius sigma + skin, and its candidates are reused while no particle has
// moved more than skin / 2 since, so that filtering them by r < sigma gives exactly
// close_pairs(x), in its order. A solver's line-search trials and Newton iterations then cost a
// filter over the candidates instead of a hash of all particles.
#include <algorithm>
#include <vector>

#include "woven/model/cloth_model.hpp"

namespace woven::model {

class PairCache {
public:
    /// `skin` in sigma (> 0).
    explicit PairCache(const ClothModel& model, double skin = 0.5) : model_(model), skin_(skin * model.sigma()) {}

    /// close_pairs(x): the pairs i < j of active particles closer than sigma, ascending.
    const std::vector<Stencil<2>>& pairs(const Positions& x)
    {
        if (!valid(x)) rebuild(x);
        const double s2 = model_.sigma() * model_.sigma();
        pairs_.clear();
        for (const Stencil<2>& c : candidates_)
            if ((x[c[0]] - x[c[1]]).squaredNorm() < s2) pairs_.push_back(c);
        return pairs_;
    }
    /// Candidate rebuilds so far (spatial hashes).
    int rebuilds() const { return rebuilds_; }

private:
    bool valid(const Positions& x) const
    {
        if (anchor_.size() != x.size()) return false;
        const double limit2 = 0.25 * skin_ * skin_;
        for (size_t i = 0; i < x.size(); ++i)
            if ((x[i] - anchor_[i]).squaredNorm() > limit2) return false;
        return true;
    }
    void rebuild(const Positions& x)
    {
        candidates_ = model_.close_pairs(x, model_.sigma() + skin_);
        anchor_ = x;
        ++rebuilds_;
    }

    const ClothModel& model_;
    double skin_;  ///< m
    Positions anchor_;
    std::vector<Stencil<2>> candidates_, pairs_;
    int rebuilds_ = 0;
};

}  // namespace woven::model
