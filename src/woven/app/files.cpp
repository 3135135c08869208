// Helpers every job shares (files.hpp).
#include "woven/app/files.hpp"

#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>

#include <fcntl.h>
#include <unistd.h>

#include "woven/app/run_checks.hpp"
#include "woven/common/error.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/output_file.hpp"
#include "woven/io/output_set.hpp"

namespace woven::app {

long long integer_in_range(long long value, const ValueName& name, long long lo, long long hi)
{
    if (value < lo || value > hi)
        throw InputError(name.source, name.field,
                         "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got '" + std::to_string(value)
                             + "'");
    return value;
}

namespace {

/// A value as an error quotes it: 'text', cut after 40 characters.
std::string shown(const std::string& text) { return "'" + text.substr(0, 40) + (text.size() > 40 ? "...'" : "'"); }

std::string shortest(double value)
{
    char v[32];
    const auto r = std::to_chars(v, v + sizeof v, value);
    return std::string(v, r.ptr);
}

}  // namespace

long long integer_from_text(const std::string& text, const ValueName& name, long long lo, long long hi)
{
    long long v = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
    if (r.ec != std::errc() || r.ptr != text.data() + text.size() || v < lo || v > hi)
        throw InputError(name.source, name.field,
                         "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + shown(text));
    return v;
}

std::uint64_t seed_from_text(const std::string& text, const ValueName& name)
{
    std::uint64_t v = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
    if (r.ec != std::errc() || r.ptr != text.data() + text.size())
        throw InputError(name.source, name.field,
                         "expected an integer in [0, " + std::to_string(std::numeric_limits<std::uint64_t>::max()) + "], got "
                             + shown(text));
    return v;
}

double positive_from_text(const std::string& text, const ValueName& name, double hi)
{
    double v = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
    if (r.ec != std::errc() || r.ptr != text.data() + text.size() || !std::isfinite(v) || !(v > 0) || v > hi) {
        char h[32];
        std::snprintf(h, sizeof h, "%g", hi);
        throw InputError(name.source, name.field, "expected a number in (0, " + std::string(h) + "], got " + shown(text));
    }
    return v;
}

double number_from_text(const std::string& text, const ValueName& name, double lo, double hi)
{
    double v = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
    if (r.ec != std::errc() || r.ptr != text.data() + text.size() || !std::isfinite(v) || v < lo || v > hi) {
        char b[64];
        std::snprintf(b, sizeof b, "[%g, %g]", lo, hi);
        throw InputError(name.source, name.field, "expected a number in " + std::string(b) + ", got " + shown(text));
    }
    return v;
}

double positive_in_range(double value, const ValueName& name, double hi)
{
    if (!std::isfinite(value) || !(value > 0) || value > hi) {
        char h[32];
        std::snprintf(h, sizeof h, "%g", hi);
        throw InputError(name.source, name.field, "expected a number in (0, " + std::string(h) + "], got '" + shortest(value) + "'");
    }
    return value;
}

std::string path_given(const std::string& path, const ValueName& name)
{
    if (path.empty()) throw InputError(name.source, name.field, "expected a directory path, got an empty string");
    return path;
}

std::optional<std::string> path_given(const std::optional<std::filesystem::path>& path, const ValueName& name)
{
    if (!path) return std::nullopt;
    return path_given(path->string(), name);
}

std::size_t choice_index(const std::string& text, const ValueName& name, std::span<const char* const> names)
{
    std::string expected;
    std::size_t k = 0;
    for (const char* c : names) {
        if (text == c) return k;
        expected += (k == 0 ? "" : k + 1 == names.size() ? " or " : ", ") + std::string(c);
        ++k;
    }
    throw InputError(name.source, name.field, "expected " + expected + ", got '" + text + "'");
}

double number_in_range(double value, const ValueName& name, double lo, double hi)
{
    if (!std::isfinite(value) || value < lo || value > hi) {
        char b[64];
        std::snprintf(b, sizeof b, "[%g, %g]", lo, hi);
        throw InputError(name.source, name.field, "expected a number in " + std::string(b) + ", got '" + shortest(value) + "'");
    }
    return value;
}

std::string keyword_of(std::string_view option)
{
    std::string k(option.substr(option.rfind("--", 0) == 0 ? 2 : 0));
    for (char& c : k)
        if (c == '-') c = '_';
    return k;
}

ValueName value_name(Naming naming, std::string_view option, std::string_view keyword)
{
    if (naming == Naming::OPTIONS) return ValueName(kCommandLine, std::string(option));
    return ValueName("", keyword.empty() ? keyword_of(option) : std::string(keyword));
}

long long integer_value(const Given<long long>& value, const ValueName& name, long long lo, long long hi)
{
    if (const auto* v = std::get_if<long long>(&value)) return integer_in_range(*v, name, lo, hi);
    return integer_from_text(std::get<std::string>(value), name, lo, hi);
}

std::uint64_t seed_value(const Given<std::uint64_t>& value, const ValueName& name)
{
    if (const auto* v = std::get_if<std::uint64_t>(&value)) return *v;
    return seed_from_text(std::get<std::string>(value), name);
}

double number_value(const Given<double>& value, const ValueName& name, double lo, double hi)
{
    if (const auto* v = std::get_if<double>(&value)) return number_in_range(*v, name, lo, hi);
    return number_from_text(std::get<std::string>(value), name, lo, hi);
}

double positive_value(const Given<double>& value, const ValueName& name, double hi)
{
    if (const auto* v = std::get_if<double>(&value)) return positive_in_range(*v, name, hi);
    return positive_from_text(std::get<std::string>(value), name, hi);
}

std::optional<std::string> read_output_file(const std::string& path)
{
    try {
        return io::read_output_member(path);
    } catch (const InputError&) {
        return std::nullopt;
    }
}

/// One line: control characters (a newline from an input file) shown as \xNN.
std::string one_line(const std::string& s)
{
    std::string out;
    for (const char c : s) {
        if (static_cast<unsigned char>(c) < 0x20) {
            char b[8];
            std::snprintf(b, sizeof b, "\\x%02x", static_cast<unsigned char>(c));
            out += b;
        } else {
            out += c;
        }
    }
    return out;
}

void make_output_dir(const std::string& dir)
{
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) {
        if (fs::exists(dir, ec)) throw InputError(kCommandLine, "--out", dir + " exists and is not a directory");
        fs::create_directories(dir, ec);
        // An I/O failure (exit 1), not bad input: the name is well formed, the system refuses it.
        if (ec) throw RuntimeError(std::string(kCommandLine) + ": --out: cannot create the directory " + dir + ": " + ec.message());
    }
    // Writable now, not after the run (a read-only folder let a drape solve for minutes, then
    // fail): a probe file made and removed.
    const std::string probe = join_path(dir, std::string(io::kTempPrefix) + std::to_string(::getpid()) + ".probe");
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
    if (fd < 0 && errno != EEXIST)
        throw RuntimeError(std::string(kCommandLine) + ": --out: cannot write into the directory " + dir + ": " + std::strerror(errno));
    if (fd >= 0) {
        ::close(fd);
        ::unlink(probe.c_str());
    }
    // Held open from now: the set is published into this folder even if the path is swapped
    // for a symlink while the run works.
    io::hold_output_dir(dir);
}

std::string safe_file_name(const std::string& text)
{
    std::string s = text.substr(0, 100);
    for (char& c : s)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-')) c = '_';
    if (!s.empty() && s[0] == '.') s[0] = '_';
    return s.empty() ? std::string("unnamed") : s;
}

std::string join_path(const std::string& dir, const std::string& name)
{
    return (std::filesystem::path(dir) / name).string();
}

kes::FabricData command_fabric(const std::string& name, const GivenFabric& given, std::vector<std::string>* warnings)
{
    return given.data ? *given.data : io::find_fabric(name, warnings);
}

std::string command_fabric_source(const std::string& name, const GivenFabric& given)
{
    return given.data ? given.source : fabric_source(name);
}

}  // namespace woven::app
