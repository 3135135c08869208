#include "woven/cli/args.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>

#include "woven/common/error.hpp"

namespace woven::cli {

namespace {

std::string shown(const std::string& text) { return "'" + text.substr(0, 40) + (text.size() > 40 ? "...'" : "'"); }

}  // namespace

long long parse_integer(const std::string& text, const std::string& option, long long lo, long long hi)
{
    long long v = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
    if (r.ec != std::errc() || r.ptr != text.data() + text.size() || v < lo || v > hi)
        throw InputError(kCommandLine, option,
                         "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                             shown(text));
    return v;
}

std::optional<long long> parse_integer(const std::optional<std::string>& text, const std::string& option, long long lo,
                                       long long hi)
{
    if (!text) return std::nullopt;
    return parse_integer(*text, option, lo, hi);
}

std::uint64_t parse_seed(const std::string& text, const std::string& option)
{
    std::uint64_t v = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
    if (r.ec != std::errc() || r.ptr != text.data() + text.size())
        throw InputError(kCommandLine, option,
                         "expected an integer in [0, " + std::to_string(std::numeric_limits<std::uint64_t>::max()) +
                             "], got " + shown(text));
    return v;
}

double parse_positive(const std::string& text, const std::string& option, double hi)
{
    double v = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
    if (r.ec != std::errc() || r.ptr != text.data() + text.size() || !std::isfinite(v) || !(v > 0) || v > hi) {
        char h[32];
        std::snprintf(h, sizeof h, "%g", hi);
        throw InputError(kCommandLine, option, "expected a number in (0, " + std::string(h) + "], got " + shown(text));
    }
    return v;
}

double parse_number(const std::string& text, const std::string& option, double lo, double hi)
{
    double v = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
    if (r.ec != std::errc() || r.ptr != text.data() + text.size() || !std::isfinite(v) || v < lo || v > hi) {
        char b[64];
        std::snprintf(b, sizeof b, "[%g, %g]", lo, hi);
        throw InputError(kCommandLine, option, "expected a number in " + std::string(b) + ", got " + shown(text));
    }
    return v;
}

std::string parse_path(const std::string& text, const std::string& option)
{
    if (text.empty()) throw InputError(kCommandLine, option, "expected a directory path, got an empty string");
    return text;
}

std::size_t parse_choice(const std::string& text, const std::string& option, std::initializer_list<const char*> choices)
{
    return parse_choice(text, option, std::span<const char* const>(choices.begin(), choices.size()));
}

std::size_t parse_choice(const std::string& text, const std::string& option, std::span<const char* const> choices)
{
    std::string expected;
    std::size_t k = 0;
    for (const char* c : choices) {
        if (text == c) return k;
        expected += (k == 0 ? "" : k + 1 == choices.size() ? " or " : ", ") + std::string(c);
        ++k;
    }
    throw InputError(kCommandLine, option, "expected " + expected + ", got '" + text + "'");
}

}  // namespace woven::cli
