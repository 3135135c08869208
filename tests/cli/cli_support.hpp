#pragma once
// Running the real `woven` binary (WOVEN_BINARY) from a test, in a temporary directory of its
// own: one fixture for the command-line tests.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

namespace woven::test {

/// What a run of the binary left: its exit code (-1: killed or not started), stdout, stderr.
struct Outcome {
    int code = -1;
    std::string out, err;
};

/// `s` quoted for the shell.
inline std::string quote(const std::string& s)
{
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

/// The whole file at `p` (empty if it cannot be read).
inline std::string slurp(const std::filesystem::path& p)
{
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

inline void write(const std::filesystem::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

/// `s` with the first `from` replaced by `to` (a test failure if `from` is not there).
inline std::string replace(std::string s, const std::string& from, const std::string& to)
{
    const auto at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) s.replace(at, from.size(), to);
    return s;
}

/// Exactly one line, newline-terminated (the form of every error message).
inline bool one_line(const std::string& s) { return !s.empty() && s.back() == '\n' && s.find('\n') == s.size() - 1; }

/// A 0.3 m cloth, 9 x 9, over a sphere on a floor: the command-line tests' small scene.
inline const std::string kTinyScene = R"(name = "tiny"
[cloth]
size_m = [0.3, 0.3]
grid = [9, 9]
height_m = 0.12
fabric = "cotton"
[[obstacle]]
type = "plane"
[[obstacle]]
type = "sphere"
centre_m = [0.0, 0.0, 0.05]
radius_m = 0.05
)";

/// A fresh temporary directory per test (dir_, named after the test), removed afterwards, and
/// woven run inside it.
class WovenProcessTest : public ::testing::Test {
protected:
    void SetUp() override
    {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = std::filesystem::temp_directory_path()
            / ("woven_" + std::string(info->test_suite_name()) + "_" + std::to_string(::getpid()) + "_" + info->name());
        std::filesystem::remove_all(dir_);
        std::filesystem::create_directories(dir_);
    }
    void TearDown() override
    {
        std::error_code ec;
        std::filesystem::remove_all(dir_, ec);
    }

    /// Runs `<prefix> woven <args>` in the temporary directory (prefix: e.g. `ulimit -v N;`).
    Outcome woven(const std::string& args, const std::string& prefix = "")
    {
        const std::filesystem::path err = dir_ / ".stderr";
        const std::string cmd
            = "cd " + quote(dir_.string()) + " && " + prefix + quote(WOVEN_BINARY) + " " + args + " 2>" + quote(err.string());
        Outcome r;
        FILE* p = ::popen(cmd.c_str(), "r");
        if (!p) return r;
        char buf[4096];
        std::size_t n;
        while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
        const int status = ::pclose(p);
        r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        r.err = slurp(err);
        std::filesystem::remove(err);
        return r;
    }

    std::filesystem::path dir_;
};

}  // namespace woven::test
