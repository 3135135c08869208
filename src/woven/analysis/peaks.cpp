#include "woven/analysis/peaks.hpp"

#include <algorithm>
#include <cmath>

#include "woven/common/error.hpp"

namespace woven::analysis {

std::vector<Peak> prominent_peaks(const std::vector<double>& values, double min_prominence, SequenceEnds ends)
{
    constexpr const char* kWhere = "peaks";
    if (!(min_prominence > 0)) throw InputError(kWhere, "min_prominence", "expected a positive prominence");
    const int n = static_cast<int>(values.size());
    if (n < 3) throw InputError(kWhere, "values", "expected at least 3 samples");
    // A periodic sequence is read from its global minimum round to it again: then every maximum
    // lies strictly inside s, no maximum is cut in two, and the wrap-around needs no special case.
    const bool periodic = ends == SequenceEnds::PERIODIC;
    const int start = periodic ? static_cast<int>(std::min_element(values.begin(), values.end()) - values.begin()) : 0;
    const int m = periodic ? n + 1 : n;
    std::vector<double> s(m);
    for (int k = 0; k < m; ++k) s[k] = values[(start + k) % n];
    std::vector<Peak> peaks;
    for (int k = 1; k + 1 < m;) {
        if (!(s[k] > s[k - 1])) {
            ++k;
            continue;
        }
        int j = k;  // plateau [k, j]
        while (j + 1 < m && s[j + 1] == s[k]) ++j;
        if (j + 1 >= m || s[j + 1] > s[k]) {
            k = j + 1;
            continue;
        }
        // Higher ground is the first sample above the top on each side (or an end).
        const double top = s[k];
        double left = top, right = top;
        for (int a = k - 1; a >= 0 && s[a] <= top; --a) left = std::min(left, s[a]);
        for (int b = j + 1; b < m && s[b] <= top; ++b) right = std::min(right, s[b]);
        const double prominence = top - std::max(left, right);
        if (prominence >= min_prominence) {
            double idx = 0.5 * (k + j);
            if (j == k) {
                const double ym = s[k - 1], y0 = s[k], yp = s[k + 1];
                const double den = ym - 2 * y0 + yp;
                if (den < 0) idx += 0.5 * (ym - yp) / den;
            }
            idx = std::fmod(idx + start + n, static_cast<double>(n));  // in [0, n): the parabola may step below 0
            peaks.push_back({idx, (start + (k + j) / 2) % n, top, prominence});
        }
        k = j + 1;
    }
    std::sort(peaks.begin(), peaks.end(), [](const Peak& a, const Peak& b) { return a.index < b.index; });
    return peaks;
}

}  // namespace woven::analysis
