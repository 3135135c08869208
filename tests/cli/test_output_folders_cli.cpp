// What the commands read back from output and sweep folders, and how they run under limits:
// a deep or FIFO manifest neither crashes nor blocks check, report or sweep; a small address-
// space limit does not hang the process at exit; cusick is held to the drape's memory
// estimate; sweep plans (FIFO, non-fabric files, quoting of --list) and planted symlinks.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sys/stat.h>

#include "cli_support.hpp"

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using woven::test::one_line;
using woven::test::Outcome;
using woven::test::write;

namespace {

using OutputFolderCli = woven::test::WovenProcessTest;

/// Every command is run under `timeout`: a hang fails the test instead of blocking it.
const std::string kLimit = "timeout -s KILL 60 ";

}  // namespace

TEST_F(OutputFolderCli, DeepManifestIsRefusedNotACrash)
{
    fs::create_directories(dir_ / "res");
    write(dir_ / "res" / "report.json", std::string(60000, '[') + std::string(60000, ']'));
    for (const char* args : {"check res", "report res"}) {
        const Outcome r = woven(args, kLimit);
        EXPECT_EQ(r.code, 2) << args << ": " << r.err;
        EXPECT_TRUE(one_line(r.err)) << args << ": " << r.err;
        EXPECT_THAT(r.err, HasSubstr("res/report.json: json: expected")) << args;
        EXPECT_THAT(r.err, HasSubstr("nested at most 64 deep")) << args;
    }
}

TEST_F(OutputFolderCli, FifoAndDeviceManifestsDoNotBlock)
{
    fs::create_directories(dir_ / "res");
    ASSERT_EQ(::mkfifo((dir_ / "res" / "report.json").c_str(), 0644), 0);
    for (const char* args : {"check res", "report res"}) {
        const Outcome r = woven(args, kLimit);
        EXPECT_EQ(r.code, 2) << args << ": " << r.err;
        EXPECT_THAT(r.err, HasSubstr("res/report.json: file: is not a regular file (a device, FIFO or socket)")) << args;
    }
    fs::remove(dir_ / "res" / "report.json");
    fs::create_symlink("/dev/zero", dir_ / "res" / "cusick.json");
    const Outcome z = woven("check res", kLimit);
    EXPECT_EQ(z.code, 2) << z.err;
    EXPECT_THAT(z.err, HasSubstr("res/cusick.json: file: is not a regular file"));
}

TEST_F(OutputFolderCli, SweepPointWithAFifoManifestIsRerunNotBlocked)
{
    write(dir_ / "p.toml", "command = \"kes-test\"\n[options]\ntest = \"cantilever\"\ndirection = \"warp\"\n[axes]\nfabric = [\"cotton\"]\n");
    fs::create_directories(dir_ / "out" / "fabric-cotton");
    ASSERT_EQ(::mkfifo((dir_ / "out" / "fabric-cotton" / "kes-report.json").c_str(), 0644), 0);
    const Outcome r = woven("sweep p.toml --out out --merge", kLimit);
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_THAT(r.out, HasSubstr("0 done, 0 failed, 1 missing"));
    EXPECT_THAT(woven::test::slurp(dir_ / "out" / "sweep.json"), HasSubstr("is not a regular file"));
}

TEST_F(OutputFolderCli, VersionEndsUnderASmallAddressSpaceLimit)
{
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "AddressSanitizer reserves more address space than the limit set here";
#else
    // OpenBLAS's threads could not map their buffers and spun for ever at exit.
    for (const char* limit : {"150000", "200000"}) {
        const Outcome r = woven("--version", std::string("ulimit -v ") + limit + "; " + kLimit);
        EXPECT_EQ(r.code, 0) << limit << ": " << r.err;
        EXPECT_THAT(r.out, HasSubstr("woven ")) << limit;
        // Issue 53: a thread count the user set was kept, and spun (64 under 200000: never ended).
        const Outcome set = woven("--version", std::string("ulimit -v ") + limit + "; export OPENBLAS_NUM_THREADS=64; " + kLimit);
        EXPECT_EQ(set.code, 0) << limit << ": " << set.err;
        EXPECT_THAT(set.out, HasSubstr("woven ")) << limit;
    }
#endif
}

TEST_F(OutputFolderCli, CusickIsHeldToTheDrapeMemoryEstimate)
{
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "AddressSanitizer reserves more address space than the limit set here";
#else
    // 282,681 particles: about 4 GB; refused at once under a 2 GB address space, naming the option.
    const Outcome r = woven("cusick cotton --spacing-cm 0.05 --out c", "ulimit -v 2000000; " + kLimit);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_TRUE(one_line(r.err)) << r.err;
    EXPECT_THAT(r.err, HasSubstr("command line: --spacing-cm: "));
    EXPECT_THAT(r.err, HasSubstr("particles need about"));
    EXPECT_THAT(r.err, HasSubstr("use a larger --spacing-cm"));
    EXPECT_FALSE(fs::exists(dir_ / "c"));
#endif
}

TEST_F(OutputFolderCli, SweepPlansThatAreNotFilesOrNotFabrics)
{
    ASSERT_EQ(::mkfifo((dir_ / "fifo.toml").c_str(), 0644), 0);
    const Outcome f = woven("sweep fifo.toml", kLimit);
    EXPECT_EQ(f.code, 2);
    EXPECT_EQ(f.err, "woven: error: fifo.toml: file: is not a regular file (a device, FIFO or socket); expected a sweep plan .toml file\n");
    const Outcome z = woven("sweep /dev/zero", kLimit);
    EXPECT_EQ(z.code, 2);
    EXPECT_THAT(z.err, HasSubstr("/dev/zero: file: is not a regular file"));
    // A scene file given as a fabric: refused before any point runs (exit 2), not failing late.
    write(dir_ / "p.toml", "command = \"kes-test\"\n[axes]\nfabric = [\"" + std::string(WOVEN_SOURCE_DIR) + "/scenes/cube.toml\"]\n");
    const Outcome s = woven("sweep p.toml --out out", kLimit);
    EXPECT_EQ(s.code, 2) << s.err;
    EXPECT_TRUE(one_line(s.err)) << s.err;
    EXPECT_THAT(s.err, HasSubstr("p.toml: axes.fabric[1]: expected a built-in fabric"));
    EXPECT_FALSE(fs::exists(dir_ / "out"));
}

TEST_F(OutputFolderCli, SweepListQuotesItsCommandLines)
{
    write(dir_ / "my wool's.toml", woven::test::slurp(fs::path(WOVEN_SOURCE_DIR) / "fabrics" / "wool.toml"));
    write(dir_ / "p.toml", "command = \"kes-test\"\n[axes]\nfabric = [\"my wool's.toml\"]\n\"fabric.name\" = [\"a b\"]\n");
    const Outcome l = woven("sweep p.toml --list", kLimit);
    EXPECT_EQ(l.code, 0) << l.err;
    EXPECT_EQ(l.out, "0 fabric-my_wool_s_fabric.name-a_b: kes-test '" + (dir_ / "my wool'\\''s.toml").string() +
                         "' 'fabric.name=\"a b\"'\n");
}

TEST_F(OutputFolderCli, ASweepRefusesAPlantedFailedLink)
{
    write(dir_ / "p.toml", "command = \"kes-test\"\n[options]\ntest = \"cantilever\"\ndirection = \"warp\"\n[axes]\nfabric = [\"cotton\"]\n");
    fs::create_directories(dir_ / "out");
    fs::create_directories(dir_ / "elsewhere");
    fs::create_directory_symlink(dir_ / "elsewhere", dir_ / "out" / "failed");
    const Outcome r = woven("sweep p.toml --out out", kLimit);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_THAT(r.err, HasSubstr("out/failed is a symbolic link; expected the sweep's own folder"));
    EXPECT_TRUE(fs::is_empty(dir_ / "elsewhere"));
}

TEST_F(OutputFolderCli, ASweepOfDrapesIsHeldToTheEstimateBeforeAPointRuns)
{
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "AddressSanitizer reserves more address space than the limit set here";
#else
    // The experiments' drapes run as a sweep's points: the largest is estimated before the first
    // starts (a point refusing itself later made the sweep fail with exit 1).
    write(dir_ / "p.toml", "command = \"drape\"\n[axes]\ngrid = [9, 1000]\n");
    const Outcome r = woven("sweep p.toml --out out", "ulimit -v 4000000; " + kLimit);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_TRUE(one_line(r.err)) << r.err;
    EXPECT_THAT(r.err, HasSubstr("p.toml: point grid-1000: 1000000 particles need about"));
    EXPECT_FALSE(fs::exists(dir_ / "out" / "grid-9"));
#endif
}

// Issue 53 item 9: a drape into a folder it cannot write ran the whole solve, then failed. Now
// the folder is tried before the run: one line, exit 1, no step drawn.
TEST_F(OutputFolderCli, AFolderThatCannotBeWrittenIsRefusedBeforeTheRun)
{
    fs::create_directories(dir_ / "ro");
    // Immutable: even root cannot make a file in it (the tests may run as root).
    if (std::system(("chattr +i " + (dir_ / "ro").string() + " 2>/dev/null").c_str()) != 0)
        GTEST_SKIP() << "chattr +i is not permitted here";
    write(dir_ / "tiny.toml", woven::test::kTinyScene);
    const Outcome r = woven("drape tiny.toml --no-render --threads 1 --out ro");
    [[maybe_unused]] const int undo = std::system(("chattr -i " + (dir_ / "ro").string()).c_str());
    EXPECT_EQ(r.code, 1) << r.err;
    EXPECT_TRUE(one_line(r.err)) << r.err;
    EXPECT_THAT(r.err, HasSubstr("command line: --out: cannot write into the directory ro: Operation not permitted"));
}
