// woven sweep and woven report on the command line: help, and every bad plan, option or folder
// gives the one-line error "woven: error: <source>: <field>: <expected>" with exit 2 and writes
// nothing. (The runs themselves: tests/sweep/test_sweep.py, Sweep.* and Report.Chromium.)
#include <filesystem>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "cli_support.hpp"

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using woven::test::one_line;
using woven::test::write;

namespace {

using SweepCli = woven::test::WovenProcessTest;

}  // namespace

TEST_F(SweepCli, HelpAndBadUsage)
{
    for (const char* args : {"sweep --help", "report --help"}) {
        const auto r = woven(args);
        EXPECT_EQ(r.code, 0) << args;
        EXPECT_THAT(r.out, HasSubstr("Usage")) << args;
    }
    write(dir_ / "p.toml", "command = \"cusick\"\n[axes]\nfabric = [\"cotton\"]\nseed = [1, 2]\n");
    write(dir_ / "bad.toml", "command = \"cusick\"\n[axes]\nfabric = [\"cotton\"]\nseed = [1, 1.5]\n");
    write(dir_ / "over.toml", "command = \"kes-test\"\n[axes]\nfabric = [\"wool\"]\n\"fabric.shear.Q\" = [1]\n");
    const struct {
        const char* args;
        const char* message;
    } cases[] = {
        {"sweep none.toml", "woven: error: none.toml: file: no such plan file\n"},
        {"sweep bad.toml", "woven: error: bad.toml: axes.seed[2]: expected an integer in [0, 9000000000000000], got 1.5 (line 4)\n"},
        {"sweep p.toml --jobs 0", "woven: error: command line: --jobs: expected an integer in [1, 4096], got '0'\n"},
        {"sweep p.toml --shard 3", "woven: error: command line: --shard: expected I/N with 0 <= I < N (shard I of N, counted from 0), got '3'\n"},
        {"sweep p.toml --out ''", "woven: error: command line: --out: expected a directory path, got an empty string\n"},
        {"sweep over.toml", "unknown key, ignored (an override names a key the file does not have)\n"},
        {"report nowhere", "woven: error: nowhere: no such folder\n"},
        {"report .", "woven: error: .: expected a sweep folder (sweep.json), an output folder of drape, cusick, kes-test, fit or garment"},
    };
    for (const auto& c : cases) {
        const auto r = woven(c.args);
        EXPECT_EQ(r.code, 2) << c.args << ": " << r.err;
        EXPECT_TRUE(one_line(r.err)) << c.args << ": " << r.err;
        EXPECT_THAT(r.err, HasSubstr(c.message)) << c.args;
    }
    EXPECT_FALSE(fs::exists(dir_ / "out"));
    // --list runs nothing and shows each point's command line.
    const auto l = woven("sweep p.toml --list");
    EXPECT_EQ(l.code, 0) << l.err;
    EXPECT_EQ(l.out, "0 fabric-cotton_seed-1: cusick cotton --seed 1\n1 fabric-cotton_seed-2: cusick cotton --seed 2\n");
    EXPECT_FALSE(fs::exists(dir_ / "out"));
}
