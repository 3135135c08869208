#pragma once
// For the reliability tests: woven started in the background (to be signalled or raced), the
// documented error form, and the check that an output set is complete.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "woven/io/sha256.hpp"

#include "cli_support.hpp"

namespace woven::test {

/// The documented form of an error: "woven: error: <source>: <field>: <what is expected>",
/// where <source> may carry ":<line>[:<column>]".
inline bool documented_form(const std::string& err)
{
    static const std::regex form(R"(woven: error: [^:\n]+(:[0-9]+){0,2}: [^\n:]+: [^\n]+\n)");
    return std::regex_match(err, form);
}

class SpawningProcessTest : public WovenProcessTest {
protected:
    /// Starts woven with `args` (stdout to /dev/null, stderr to err.txt); returns its pid.
    pid_t spawn(const std::vector<std::string>& args)
    {
        const std::filesystem::path err = dir_ / "err.txt";
        const pid_t pid = ::fork();
        if (pid == 0) {
            if (::chdir(dir_.c_str()) != 0) ::_exit(99);
            if (!std::freopen(err.c_str(), "w", stderr) || !std::freopen("/dev/null", "w", stdout)) ::_exit(99);
            std::vector<char*> argv{const_cast<char*>(WOVEN_BINARY)};
            for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
            argv.push_back(nullptr);
            ::execv(WOVEN_BINARY, argv.data());
            ::_exit(98);
        }
        return pid;
    }

    /// Waits until err.txt contains `text` (true) or the process exits (false).
    bool wait_for(pid_t pid, const std::string& text, int& status, bool& exited)
    {
        exited = false;
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(300);
        while (std::chrono::steady_clock::now() < deadline) {
            if (::waitpid(pid, &status, WNOHANG) == pid) {
                exited = true;
                return false;
            }
            if (slurp(dir_ / "err.txt").find(text) != std::string::npos) return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        return false;
    }

    /// The set in `sub` is complete: `manifest` exists and every file it names (and only those,
    /// besides itself) is there with its checksum; no temporaries.
    ::testing::AssertionResult complete_set(const std::string& sub, const std::string& manifest = "report.json")
    {
        namespace fs = std::filesystem;
        const fs::path d = dir_ / sub;
        if (!fs::exists(d / manifest)) return ::testing::AssertionFailure() << "no " << manifest;
        const auto j = nlohmann::json::parse(slurp(d / manifest));
        std::size_t named = 0;
        for (const auto& [name, f] : j.at("files").items()) {
            ++named;
            if (!fs::exists(d / name)) return ::testing::AssertionFailure() << name << " missing";
            if (woven::io::sha256_hex(slurp(d / name)) != f.at("sha256").get<std::string>())
                return ::testing::AssertionFailure() << name << " is not the file the manifest names";
        }
        std::size_t present = 0;
        for (const auto& e : fs::directory_iterator(d)) {
            const std::string n = e.path().filename().string();
            if (n.rfind(".woven-tmp.", 0) == 0) return ::testing::AssertionFailure() << "temporary " << n << " left";
            ++present;
        }
        if (present != named + 1) return ::testing::AssertionFailure() << present << " files, " << manifest << " names " << named;
        return ::testing::AssertionSuccess();
    }
};

}  // namespace woven::test
