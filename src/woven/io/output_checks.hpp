#pragma once
// No output holds a non-finite number: the checks a job makes on its positions, its reports and
// its tables before any file of its set is staged.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "woven/common/types.hpp"

namespace woven::io {

/// Throws RuntimeError("<what> ended with non-finite positions; no outputs written") if any
/// coordinate of `x` is not finite: called before any output of a drape is staged.
void require_finite_positions(const Positions& x, const std::string& what);

/// Throws RuntimeError naming the first field of the object `report` that is null or not a
/// finite number (JSON cannot hold inf/NaN: they are written as null), so that no report with a
/// non-finite number is ever written, let alone one claiming convergence. Top-level keys in
/// `optional` may be null (an analysis that does not apply) and are not checked.
void require_finite(const nlohmann::json& report, const std::string& what,
                    const std::vector<std::string>& optional = {});

/// Throws RuntimeError("<what> ended with a non-finite number (<name>, line <n>); no outputs
/// written") if a field of the CSV text `csv` (after its header line) is a non-finite number
/// (nan, inf, as printf or iostream write them): every table a command writes is checked
/// before its set is published.
void require_finite_csv(const std::string& csv, const std::string& name, const std::string& what);

}  // namespace woven::io
