#include "woven/cli/args.hpp"

#include <iostream>

#include "woven/cli/commands.hpp"
#include "woven/common/error.hpp"
#include "woven/common/format.hpp"

namespace woven::cli {

long long parse_integer(const std::string& text, const std::string& option, long long lo, long long hi)
{
    return integer_from_text(text, option, lo, hi);
}

std::optional<long long> parse_integer(const std::optional<std::string>& text, const std::string& option, long long lo,
                                       long long hi)
{
    if (!text) return std::nullopt;
    return parse_integer(*text, option, lo, hi);
}

std::uint64_t parse_seed(const std::string& text, const std::string& option) { return seed_from_text(text, option); }

double parse_positive(const std::string& text, const std::string& option, double hi) { return positive_from_text(text, option, hi); }

double parse_number(const std::string& text, const std::string& option, double lo, double hi)
{
    return number_from_text(text, option, lo, hi);
}

std::string parse_path(const std::string& text, const std::string& option)
{
    return path_given(text, option);
}

std::size_t parse_choice(const std::string& text, const std::string& option, std::initializer_list<const char*> choices)
{
    return parse_choice(text, option, std::span<const char* const>(choices.begin(), choices.size()));
}

std::size_t parse_choice(const std::string& text, const std::string& option, std::span<const char* const> choices)
{
    return choice_index(text, option, choices);
}

void print_line(const std::string& line, bool out)
{
    // One write with its newline: the lines of processes sharing a stream (the ranks of mpirun)
    // do not cut into each other.
    (out ? std::cout : std::cerr) << (line + "\n") << std::flush;
}

void print_warnings(const std::vector<std::string>& warnings)
{
    for (const auto& w : warnings) std::cerr << "woven: warning: " << one_line(w) << "\n";
}

model::ShearLaw parse_shear_law(const std::string& text, const std::string& option)
{
    return parse_choice(text, option, model::kShearLawNames);
}

model::Hysteresis parse_hysteresis(const std::string& text, const std::string& option)
{
    return parse_choice(text, option, model::kHysteresisNames);
}

model::BiasBending parse_bias_bending(const std::string& text, const std::string& option)
{
    return parse_choice(text, option, model::kBiasBendingNames);
}

std::string int_type(long long lo, long long hi) { return "INT in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]"; }

std::string number_type(double lo, double hi) { return "NUMBER in [" + format_g(lo) + ", " + format_g(hi) + "]"; }

std::string positive_type(double hi) { return "NUMBER in (0, " + format_g(hi) + "]"; }

}  // namespace woven::cli
