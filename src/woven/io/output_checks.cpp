#include "woven/io/output_checks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>

#include "woven/common/error.hpp"

namespace woven::io {

namespace {

std::optional<std::string> first_non_finite(const nlohmann::json& j, const std::string& path)
{
    if (j.is_null()) return path;
    if (j.is_number_float() && !std::isfinite(j.get<double>())) return path;
    if (j.is_object())
        for (auto it = j.begin(); it != j.end(); ++it)
            if (auto p = first_non_finite(it.value(), path.empty() ? it.key() : path + "." + it.key())) return p;
    if (j.is_array())
        for (std::size_t k = 0; k < j.size(); ++k)
            if (auto p = first_non_finite(j[k], path + "[" + std::to_string(k) + "]")) return p;
    return std::nullopt;
}

}  // namespace

void require_finite_positions(const Positions& x, const std::string& what)
{
    for (const Vec3& p : x)
        if (!p.allFinite()) throw RuntimeError(what + " ended with non-finite positions; no outputs written");
}

void require_finite(const nlohmann::json& report, const std::string& what, const std::vector<std::string>& optional)
{
    for (auto it = report.begin(); it != report.end(); ++it) {
        if (std::find(optional.begin(), optional.end(), it.key()) != optional.end()) continue;
        if (auto p = first_non_finite(it.value(), it.key()))
            throw RuntimeError(what + " ended with a non-finite number (" + *p + "); no outputs written");
    }
}

void require_finite_csv(const std::string& csv, const std::string& name, const std::string& what)
{
    std::size_t pos = csv.find('\n'), line = 1;
    while (pos != std::string::npos && pos + 1 < csv.size()) {
        ++line;
        const std::size_t end = std::min(csv.find('\n', pos + 1), csv.size());
        std::size_t b = pos + 1;
        while (b <= end) {
            std::size_t e = csv.find(',', b);
            if (e == std::string::npos || e > end) e = end;
            std::string field = csv.substr(b, e - b);
            char* stop = nullptr;
            const double v = std::strtod(field.c_str(), &stop);
            const bool number = !field.empty() && stop == field.c_str() + field.size();
            if (number && !std::isfinite(v))
                throw RuntimeError(what + " ended with a non-finite number (" + name + ", line " + std::to_string(line) +
                                   "); no outputs written");
            b = e + 1;
        }
        pos = end < csv.size() ? end : std::string::npos;
    }
}

}  // namespace woven::io
