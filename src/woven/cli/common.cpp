// Helpers every command shares (commands.hpp).
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "woven/cli/args.hpp"
#include "woven/cli/commands.hpp"
#include "woven/cli/run_checks.hpp"
#include "woven/common/error.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/output_file.hpp"
#include "woven/io/output_set.hpp"

namespace woven::cli {

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

void print_warnings(const std::vector<std::string>& warnings)
{
    for (const auto& w : warnings) std::cerr << "woven: warning: " << one_line(w) << "\n";
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

}  // namespace woven::cli
