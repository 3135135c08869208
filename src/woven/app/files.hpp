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
#include <string_view>
#include <variant>
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

/// Where an error in a request's value points: its source and field. From an option's name
/// alone: the command line's ("command line: --grid: ..."); a Python keyword has no source
/// ("grid: ...", value_name).
struct ValueName {
    std::string source = kCommandLine;
    std::string field;
    ValueName(const char* option) : field(option) {}
    ValueName(std::string option) : field(std::move(option)) {}
    ValueName(std::string source_, std::string field_) : source(std::move(source_)), field(std::move(field_)) {}
};

/// How a front end's errors name a request's values: by the command's options or by the
/// Python module's keywords.
enum class Naming { OPTIONS, KEYWORDS };
/// The keyword of an option: "--max-steps" -> "max_steps".
std::string keyword_of(std::string_view option);
/// The name of the value an option gives: OPTIONS: {"command line", option}; KEYWORDS:
/// {"", keyword}, the keyword keyword_of(option) unless given.
ValueName value_name(Naming naming, std::string_view option, std::string_view keyword = {});

/// `value` when in [lo, hi]; InputError "command line: <field>: expected an integer in [lo, hi],
/// got '<value>'" otherwise.
long long integer_in_range(long long value, const ValueName& name, long long lo, long long hi);
/// The integer `text` holds when in [lo, hi] (a command-line value, an environment variable);
/// InputError "command line: <field>: expected an integer in [lo, hi], got '<text>'" otherwise.
long long integer_from_text(const std::string& text, const ValueName& name, long long lo, long long hi);
/// The unsigned 64-bit integer `text` holds (a seed: 0 .. 18446744073709551615, nothing clamped).
std::uint64_t seed_from_text(const std::string& text, const ValueName& name);
/// The finite number `text` holds when in (0, hi] ("expected a number in (0, hi], got 'x'").
double positive_from_text(const std::string& text, const ValueName& name, double hi);
/// The finite number `text` holds when in [lo, hi] ("expected a number in [lo, hi], got 'x'").
double number_from_text(const std::string& text, const ValueName& name, double lo, double hi);
/// `value` when finite and in (0, hi]; InputError "... expected a number in (0, hi], got '<value>'".
double positive_in_range(double value, const ValueName& name, double hi);
/// `value` when finite and in [lo, hi]; InputError "... expected a number in [lo, hi], got '<value>'".
double number_in_range(double value, const ValueName& name, double lo, double hi);

/// A request's value as a front end got it: typed (a Python int or float) or as text (a
/// command-line option's, a Python str), read and checked once by the *_value functions.
template <class T> using Given = std::variant<T, std::string>;
/// The value checked as integer_in_range (typed) or integer_from_text (text) check it; the same
/// message either way.
long long integer_value(const Given<long long>& value, const ValueName& name, long long lo, long long hi);
std::uint64_t seed_value(const Given<std::uint64_t>& value, const ValueName& name);
double number_value(const Given<double>& value, const ValueName& name, double lo, double hi);
double positive_value(const Given<double>& value, const ValueName& name, double hi);

/// `path` when not empty; InputError "command line: <field>: expected a directory path, got an
/// empty string" otherwise. The optional version: nullopt stays nullopt.
std::string path_given(const std::string& path, const ValueName& name);
std::optional<std::string> path_given(const std::optional<std::filesystem::path>& path, const ValueName& name);

/// The value `text` names in an enum's table of names (common/choice.hpp); InputError
/// "command line: <field>: expected a, b or c, got 'x'" otherwise.
std::size_t choice_index(const std::string& text, const ValueName& name, std::span<const char* const> names);
template <class E, std::size_t N> E named_choice(const std::string& text, const ValueName& name, const std::array<Named<E>, N>& table)
{
    const std::vector<const char*> names = names_of(table);
    return table[choice_index(text, name, std::span<const char* const>(names))].value;
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
