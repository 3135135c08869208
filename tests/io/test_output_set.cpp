// Output sets (issue 13 defect 6): staged under unique temporaries, published with the
// manifest last, old files of the set removed, stale temporaries cleaned; SHA-256.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include "woven/common/error.hpp"
#include "woven/io/output_set.hpp"
#include "woven/io/sha256.hpp"

namespace fs = std::filesystem;
using namespace woven;

namespace {

std::string slurp(const fs::path& p)
{
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

fs::path fresh_dir(const std::string& name)
{
    const fs::path d = fs::temp_directory_path() / ("woven_output_set_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

std::vector<std::string> entries(const fs::path& d)
{
    std::vector<std::string> n;
    for (const auto& e : fs::directory_iterator(d)) n.push_back(e.path().filename().string());
    std::sort(n.begin(), n.end());
    return n;
}

/// True when the manifest names exactly the files present, each with its checksum.
bool complete(const fs::path& d)
{
    if (!fs::exists(d / "report.json")) return false;
    const auto j = nlohmann::json::parse(slurp(d / "report.json"));
    for (const auto& [name, f] : j.at("files").items())
        if (!fs::exists(d / name) || io::sha256_hex(slurp(d / name)) != f.at("sha256").get<std::string>()) return false;
    return true;
}

void publish(const fs::path& d, const std::string& tag, bool with_b)
{
    io::OutputSet set(d.string(), {"a.txt", "b.txt"});
    set.add("a.txt", "a " + tag + "\n");
    if (with_b) set.add("b.txt", "b " + tag + "\n");
    nlohmann::json j;
    j["tag"] = tag;
    j["files"] = set.files_json();
    set.publish("report.json", j.dump());
}

}  // namespace

TEST(Sha256, KnownVectors)
{
    EXPECT_EQ(io::sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    EXPECT_EQ(io::sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    EXPECT_EQ(io::sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
              "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
    EXPECT_EQ(io::sha256_hex(std::string(1000000, 'a')),
              "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(OutputSet, PublishesTheFilesThenTheManifestAndNothingElse)
{
    const fs::path d = fresh_dir("publish");
    publish(d, "one", true);
    EXPECT_EQ(entries(d), (std::vector<std::string>{"a.txt", "b.txt", "report.json"}));
    EXPECT_TRUE(complete(d));
    // A rerun that writes no b.txt removes the old one: the set is this run's only.
    publish(d, "two", false);
    EXPECT_EQ(entries(d), (std::vector<std::string>{"a.txt", "report.json"}));
    EXPECT_EQ(slurp(d / "a.txt"), "a two\n");
    EXPECT_TRUE(complete(d));
    fs::remove_all(d);
}

// Issue 53 item 4: cusick --seeds 2 then --seeds 1 in one folder left shadow-seed*.png (not
// members of the second run's set) beside the new set. Every file the earlier manifest lists
// goes; a file of the user's own, a folder, a hidden name and a path out of the folder stay.
TEST(OutputSet, PublishingRemovesEveryFileTheEarlierManifestLists)
{
    const fs::path d = fresh_dir("earlier_manifest");
    {
        io::OutputSet set(d.string(), {"a.txt", "shadow-seed1.png", "shadow-seed2.png"});
        set.add("a.txt", "a\n");
        set.add("shadow-seed1.png", "1\n");
        set.add("shadow-seed2.png", "2\n");
        nlohmann::json j;
        j["files"] = set.files_json();
        // As a hostile or damaged manifest may: names outside the set's plain files.
        for (const char* n : {"sub", ".hidden", "../outside.txt", "/tmp"}) j["files"][n] = {{"bytes", 0}};
        set.publish("report.json", j.dump());
    }
    write(d / "mine.txt", "mine\n");
    write(d / ".hidden", "h\n");
    fs::create_directory(d / "sub");
    write(d.parent_path() / "outside.txt", "o\n");
    io::OutputSet set(d.string(), {"a.txt", "shadow.png"});
    set.add("a.txt", "a two\n");
    set.add("shadow.png", "s\n");
    nlohmann::json j;
    j["files"] = set.files_json();
    set.publish("report.json", j.dump());
    EXPECT_EQ(entries(d), (std::vector<std::string>{".hidden", "a.txt", "mine.txt", "report.json", "shadow.png", "sub"}));
    EXPECT_TRUE(fs::exists(d.parent_path() / "outside.txt"));
    fs::remove(d.parent_path() / "outside.txt");
    fs::remove_all(d);
}

TEST(OutputSet, AnUnpublishedSetLeavesThePreviousSetAndNoTemporaries)
{
    const fs::path d = fresh_dir("unpublished");
    publish(d, "old", true);
    {
        io::OutputSet set(d.string(), {"a.txt", "b.txt"});
        set.add("a.txt", "new a\n");
        write(set.temp_path("b.txt"), "new b\n");
        set.added("b.txt");
    }  // e.g. a failure before publish
    EXPECT_EQ(entries(d), (std::vector<std::string>{"a.txt", "b.txt", "report.json"}));
    EXPECT_EQ(slurp(d / "a.txt"), "a old\n");
    EXPECT_TRUE(complete(d));
    fs::remove_all(d);
}

TEST(OutputSet, ADirectoryInTheWayFailsBeforeAnythingChanges)
{
    const fs::path d = fresh_dir("in_the_way");
    publish(d, "old", false);
    fs::create_directory(d / "b.txt");
    io::OutputSet set(d.string(), {"a.txt", "b.txt"});
    set.add("a.txt", "new\n");
    set.add("b.txt", "new\n");
    EXPECT_THROW(set.publish("report.json", "{}"), RuntimeError);
    EXPECT_EQ(slurp(d / "a.txt"), "a old\n");
    EXPECT_TRUE(complete(d));
    fs::remove_all(d);
}

TEST(OutputSet, StaleTemporariesOfDeadProcessesAreRemoved)
{
    const fs::path d = fresh_dir("stale");
    // A child that dies (as if SIGKILLed) after staging its files.
    const pid_t child = ::fork();
    if (child == 0) {
        io::OutputSet set(d.string(), {"a.txt"});
        set.add("a.txt", "staged\n");
        ::_exit(0);  // no destructor: the temporaries stay
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    ASSERT_EQ(entries(d).size(), 1u);
    EXPECT_EQ(entries(d)[0].rfind(".woven-tmp." + std::to_string(child) + ".", 0), 0u);
    write(d / (".woven-tmp." + std::to_string(::getpid()) + ".99.mine"), "live");  // ours: kept
    write(d / "other.txt", "not ours");
    EXPECT_EQ(io::remove_stale_temporaries(d.string()), 1);
    EXPECT_EQ(entries(d), (std::vector<std::string>{".woven-tmp." + std::to_string(::getpid()) + ".99.mine", "other.txt"}));
    fs::remove_all(d);
}

TEST(OutputSet, RunsSharingADirectoryDoNotCollide)
{
    const fs::path d = fresh_dir("shared");
    std::vector<std::thread> runs;
    for (int k = 0; k < 8; ++k)
        runs.emplace_back([&, k] {
            for (int n = 0; n < 20; ++n) publish(d, std::to_string(k) + "-" + std::to_string(n), (k + n) % 2 == 0);
        });
    for (auto& t : runs) t.join();
    // Whoever published last: its whole set, nothing of the others, no temporaries.
    EXPECT_TRUE(complete(d));
    const auto j = nlohmann::json::parse(slurp(d / "report.json"));
    const std::string tag = j.at("tag");
    EXPECT_EQ(slurp(d / "a.txt"), "a " + tag + "\n");
    for (const auto& e : entries(d)) EXPECT_NE(e.rfind(".woven-tmp.", 0), 0u) << e;
    fs::remove_all(d);
}
