#pragma once
// Checks shared by the fuzz targets: a violated expectation aborts, so that libFuzzer records
// the input as a crash.
#include <cstdio>
#include <cstdlib>
#include <string_view>

namespace woven::fuzz {

/// Aborts with a message when `ok` is false ("exit 0 with a non-finite result" is a finding).
inline void require(bool ok, const char* what)
{
    if (ok) return;
    std::fprintf(stderr, "woven fuzz: accepted input gives a non-finite or invalid %s\n", what);
    std::abort();
}

/// An error message must be one non-empty line ("<file>: <field>: <what is expected>").
inline void check_one_line(std::string_view message)
{
    require(!message.empty() && message.find('\n') == std::string_view::npos, "error message (not one line)");
}

}  // namespace woven::fuzz
