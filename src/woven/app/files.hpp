#pragma once
// What every job of the application floor shares: the fabric a job runs on, its output folder,
// and the checks of a request's typed values (a front end converts text or objects; the job
// checks the ranges, so that every front end gets the same one-line error).
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "woven/common/choice.hpp"

namespace woven::kes {
struct FabricData;
}

namespace woven::app {

/// The source named by errors in a request's values: its fields are named by the command-line
/// options they stand for ("command line: --grid: expected an integer in [3, 100000], got '2'"),
/// whichever front end filled the request.
inline constexpr const char* kCommandLine = "command line";

/// `value` when in [lo, hi]; InputError "command line: <field>: expected an integer in [lo, hi],
/// got '<value>'" otherwise.
long long integer_in_range(long long value, const std::string& field, long long lo, long long hi);
/// The integer `text` holds when in [lo, hi] (a command-line value, an environment variable);
/// InputError "command line: <field>: expected an integer in [lo, hi], got '<text>'" otherwise.
long long integer_from_text(const std::string& text, const std::string& field, long long lo, long long hi);
/// The unsigned 64-bit integer `text` holds (a seed: 0 .. 18446744073709551615, nothing clamped).
std::uint64_t seed_from_text(const std::string& text, const std::string& field);
/// The finite number `text` holds when in (0, hi] ("expected a number in (0, hi], got 'x'").
double positive_from_text(const std::string& text, const std::string& field, double hi);
/// The finite number `text` holds when in [lo, hi] ("expected a number in [lo, hi], got 'x'").
double number_from_text(const std::string& text, const std::string& field, double lo, double hi);
/// `value` when finite and in (0, hi]; InputError "... expected a number in (0, hi], got '<value>'".
double positive_in_range(double value, const std::string& field, double hi);
/// `value` when finite and in [lo, hi]; InputError "... expected a number in [lo, hi], got '<value>'".
double number_in_range(double value, const std::string& field, double lo, double hi);

/// `path` when not empty; InputError "command line: <field>: expected a directory path, got an
/// empty string" otherwise. The optional version: nullopt stays nullopt.
std::string path_given(const std::string& path, const std::string& field);
std::optional<std::string> path_given(const std::optional<std::filesystem::path>& path, const std::string& field);

/// The value `text` names in an enum's table of names (common/choice.hpp); InputError
/// "command line: <field>: expected a, b or c, got 'x'" otherwise.
std::size_t choice_index(const std::string& text, const std::string& field, std::span<const char* const> names);
template <class E, std::size_t N>
E named_choice(const std::string& text, const std::string& field, const std::array<Named<E>, N>& table)
{
    const std::vector<const char*> names = names_of(table);
    return table[choice_index(text, field, std::span<const char* const>(names))].value;
}

/// A fabric given as data rather than by name or file (the Python module's woven.Fabric built
/// from values); `source` names it in messages and reports.
struct GivenFabric {
    std::shared_ptr<const kes::FabricData> data;
    std::string source;
};

/// The fabric a job runs on: `given`'s data when it has some, else io::find_fabric(name)
/// (its warnings appended to `warnings`).
kes::FabricData command_fabric(const std::string& name, const GivenFabric& given, std::vector<std::string>* warnings);
/// The name a job's fabric errors carry: `given`'s source, else fabric_source(name).
std::string command_fabric_source(const std::string& name, const GivenFabric& given);

/// A whole file the jobs wrote (a log, a picture) or an installed resource (three.js), a
/// regular file of at most 1 GiB (io::read_output_member); nullopt when it cannot be read. JSON
/// goes through io::read_output_json (depth-limited), input files through io::read_input_file.
std::optional<std::string> read_output_file(const std::string& path);

/// `s` with its control characters written as \xNN, so that a message stays one line.
std::string one_line(const std::string& s);

/// Creates `dir` (and its parents) when missing. A `dir` that exists and is not a directory, or
/// cannot be created, is bad usage: InputError "command line: --out: ...". Call only after
/// every input has been validated.
void make_output_dir(const std::string& dir);

/// An output file name made from text in an input file (a fabric's name): every character but
/// [A-Za-z0-9._-] becomes '_', a leading '.' too, so that it never leaves its folder; empty
/// becomes "unnamed".
std::string safe_file_name(const std::string& text);

/// `dir` / `name` as a string.
std::string join_path(const std::string& dir, const std::string& name);

}  // namespace woven::app
