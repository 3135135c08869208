#pragma once
// Prominent maxima of a sampled curve: the nodes of a Cusick shadow's radius r(theta)
// (drape_shadow.hpp) and the billows of a cube drape's section (folds.hpp).
#include <vector>

namespace woven::analysis {

/// A maximum of a sequence.
struct Peak {
    double index = 0;       ///< position, in samples, refined by a parabola through the top three, in [0, n)
    int sample = 0;         ///< the sample at the middle of the top (plateau)
    double value = 0;       ///< the sample value at the top
    double prominence = 0;  ///< top minus the higher of the two minima separating it from higher ground (or an open end)
};

/// How a sequence ends: OPEN (a maximum at either end is not one) or PERIODIC (it wraps around,
/// so a maximum at index 0 or spanning the end is found once).
enum class SequenceEnds { OPEN, PERIODIC };

/// The maxima of `values` with topographic prominence >= min_prominence, sorted by index. A
/// plateau counts once, at its middle; a constant sequence has none. Throws InputError if
/// min_prominence <= 0 or values has fewer than 3 samples.
std::vector<Peak> prominent_peaks(const std::vector<double>& values, double min_prominence, SequenceEnds ends);

/// prominent_peaks of a periodic sequence.
inline std::vector<Peak> periodic_peaks(const std::vector<double>& values, double min_prominence)
{
    return prominent_peaks(values, min_prominence, SequenceEnds::PERIODIC);
}

}  // namespace woven::analysis
