#pragma once
// Command-line values parsed by woven itself (not CLI11's converters), so that a bad value is
// one short line in the documented form "command line: <option>: <what is expected>", exit 2.
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "woven/app/files.hpp"
#include "woven/common/choice.hpp"
#include "woven/model/cloth_model.hpp"

namespace woven::cli {

/// The source named by errors in command-line values ("command line").
using app::kCommandLine;

/// An integer in [lo, hi] ("command line: --threads: expected an integer in [0, 4096], got '-1'").
/// --help's type of an option, from the range or the table its value is checked against:
/// "INT in [3, 100000]", "NUMBER in [0, 0.01]", "NUMBER in (0, 100]", "{fast,paper}".
std::string int_type(long long lo, long long hi);
inline std::string int_type(const long long (&range)[2]) { return int_type(range[0], range[1]); }
std::string number_type(double lo, double hi);
/// A seed's: any unsigned 64-bit integer (parse_seed).
inline constexpr const char* kSeedType = "INT in [0, 18446744073709551615]";
std::string positive_type(double hi);
template <class E, std::size_t N> std::string choice_type(const std::array<Named<E>, N>& table)
{
    std::string t = "{";
    for (const char* name : names_of(table)) t += std::string(t.size() > 1 ? "," : "") + name;
    return t + "}";
}

long long parse_integer(const std::string& text, const std::string& option, long long lo, long long hi);
/// An unsigned 64-bit integer (a seed: 0 .. 18446744073709551615, nothing clamped).
std::uint64_t parse_seed(const std::string& text, const std::string& option);
/// A finite number in (lo, hi] (lo excluded).
double parse_positive(const std::string& text, const std::string& option, double hi);
/// A finite number in [lo, hi].
double parse_number(const std::string& text, const std::string& option, double lo, double hi);
/// A non-empty path ("command line: --out: expected a directory path, got an empty string").
std::string parse_path(const std::string& text, const std::string& option);

/// The index of `text` in `choices` ("command line: --shear-law: expected deembedded or
/// measured, got 'x'").
std::size_t parse_choice(const std::string& text, const std::string& option, std::initializer_list<const char*> choices);
std::size_t parse_choice(const std::string& text, const std::string& option, std::span<const char* const> choices);
/// The value `text` names in an enum's table of names (common/choice.hpp), the same error otherwise.
template <class E, std::size_t N>
E parse_choice(const std::string& text, const std::string& option, const std::array<Named<E>, N>& table)
{
    return app::named_choice(text, option, table);
}

/// std::optional versions: nullopt stays nullopt.
std::optional<long long> parse_integer(const std::optional<std::string>& text, const std::string& option, long long lo,
                                       long long hi);

/// The law a command-line word names (`--shear-law`); InputError naming `option` otherwise.
model::ShearLaw parse_shear_law(const std::string& text, const std::string& option);
/// --hysteresis: loading-branch or friction (the one-line error otherwise).
model::Hysteresis parse_hysteresis(const std::string& text, const std::string& option);
/// The help of --bias (drape, cusick).
inline constexpr const char* kBiasBendingHelp =
    "threads (the paper's: bending along the warp and weft alone) or fabric (and the twisting that gives the fabric's bias "
    "bending rigidity, measured or estimated)";
/// "threads" or "fabric" (model::BiasBending); InputError("command line", option, ...) otherwise.
model::BiasBending parse_bias_bending(const std::string& text, const std::string& option);

}  // namespace woven::cli
