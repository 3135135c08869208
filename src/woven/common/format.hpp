#pragma once
// printf formats into a std::string (GCC 12 has no std::format).
#include <cstdarg>
#include <cstdio>
#include <string>

namespace woven {

/// `fmt` with its arguments, as printf writes them.
[[gnu::format(printf, 1, 2)]] inline std::string strf(const char* fmt, ...)
{
    va_list a, b;
    va_start(a, fmt);
    va_copy(b, a);
    const int n = std::vsnprintf(nullptr, 0, fmt, a);
    va_end(a);
    std::string s(n > 0 ? n : 0, '\0');
    if (n > 0) std::vsnprintf(s.data(), s.size() + 1, fmt, b);
    va_end(b);
    return s;
}

/// `v` in printf's %g form with `digits` significant digits ("0.25", "1.5e-05").
inline std::string format_g(double v, int digits = 6) { return strf("%.*g", digits, v); }

}  // namespace woven
