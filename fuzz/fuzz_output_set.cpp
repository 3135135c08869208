// libFuzzer target: the output set every command writes its files through (io::OutputSet;
// kes-test and experiment since issue 36), driven through sequences of runs into one folder
// that a unit test cannot enumerate. Each input is a script; after every step the folder must
// hold the last published set whole: its manifest names exactly the set's files present, each
// with the contents and SHA-256 published, no file of the set that the manifest does not name,
// and no temporary of a finished run.
//
// Script bytes, read in turn: an operation (byte % 4), then its arguments.
//   0  a run that publishes: a mask byte choosing among kMembers, then per chosen file a length
//      byte and that many content bytes (missing bytes read as 0);
//   1  a run that fails before publishing (its OutputSet is destroyed: temporaries removed);
//   2  a run that dies before publishing (a forked child stages its files and _exits, as under
//      SIGKILL; its temporaries stay until the next set in the folder is opened);
//   3  a run whose publish finds a directory where one of its files goes (a byte chooses it):
//      it must throw and leave the previous set as it was.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "fuzz_support.hpp"
#include "woven/common/error.hpp"
#include "woven/io/output_set.hpp"
#include "woven/io/sha256.hpp"

namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kMembers = {"cantilever_warp.csv", "bending.png", "shear_weft.csv", "figure1_chair.png", "figure1.md"};
const std::string kManifest = "kes-report.json";

struct Script {
    const std::uint8_t* data;
    std::size_t size, at = 0;
    bool done() const { return at >= size; }
    std::uint8_t next() { return at < size ? data[at++] : 0; }
};

std::string slurp(const fs::path& p)
{
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// The files of one run: chosen members and their contents.
std::map<std::string, std::string> files_of(Script& s)
{
    std::map<std::string, std::string> f;
    const std::uint8_t mask = s.next();
    for (std::size_t k = 0; k < kMembers.size(); ++k)
        if (mask & (1u << k)) {
            std::string text(s.next() % 64, '\0');
            for (char& c : text) c = static_cast<char>(s.next());
            f[kMembers[k]] = text;
        }
    return f;
}

void stage(woven::io::OutputSet& set, const std::map<std::string, std::string>& files)
{
    for (const auto& [name, text] : files) set.add(name, text);
}

/// The folder holds exactly `published` (name -> contents) with its manifest; `temporaries`:
/// whether temporaries of a dead run may still be there.
void check_folder(const fs::path& dir, const std::map<std::string, std::string>* published, bool temporaries)
{
    using woven::fuzz::require;
    if (!published) {  // nothing published yet: no manifest, no member
        require(!fs::exists(dir / kManifest), "folder (a manifest before any publish)");
        for (const auto& m : kMembers) require(!fs::exists(dir / m), "folder (a member before any publish)");
        return;
    }
    const auto j = nlohmann::json::parse(slurp(dir / kManifest), nullptr, false);
    require(!j.is_discarded() && j.contains("files") && j["files"].is_object(), "manifest");
    require(j["files"].size() == published->size(), "manifest (file count)");
    for (const auto& [name, text] : *published) {
        require(j["files"].contains(name), "manifest (a published file missing)");
        require(slurp(dir / name) == text, "published file (contents)");
        require(j["files"][name]["sha256"] == woven::io::sha256_hex(text), "manifest (checksum)");
        require(j["files"][name]["bytes"] == text.size(), "manifest (size)");
    }
    for (const auto& m : kMembers) require(published->count(m) == 1 || !fs::exists(dir / m), "folder (a stale member left)");
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string n = e.path().filename().string();
        if (n.rfind(woven::io::kTempPrefix, 0) == 0) {
            require(temporaries, "folder (a temporary of a finished run)");
            continue;
        }
        require(n == kManifest || published->count(n) == 1, "folder (an unexpected file)");
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    static const fs::path dir = fs::temp_directory_path() / ("woven-fuzz-output-set-" + std::to_string(::getpid()));
    std::error_code ec;
    fs::remove_all(dir, ec);
    fs::create_directories(dir);
    Script s{data, size};
    std::map<std::string, std::string> published;
    bool any = false, dead_temporaries = false;
    for (int step = 0; step < 8 && !s.done(); ++step) {
        const int op = s.next() % 4;
        const auto files = files_of(s);
        if (op == 0) {
            woven::io::OutputSet set(dir.string(), kMembers);
            dead_temporaries = false;  // opening the set removed them
            stage(set, files);
            set.publish(kManifest, nlohmann::json{{"files", set.files_json()}}.dump());
            published = files;
            any = true;
        } else if (op == 1) {
            {
                woven::io::OutputSet set(dir.string(), kMembers);
                dead_temporaries = false;
                stage(set, files);
            }
        } else if (op == 2) {
            const pid_t pid = ::fork();
            if (pid == 0) {
                woven::io::OutputSet set(dir.string(), kMembers);
                stage(set, files);
                ::_exit(0);  // no destructors: the temporaries stay, as after SIGKILL
            }
            int status = 0;
            ::waitpid(pid, &status, 0);
            dead_temporaries = dead_temporaries || !files.empty();
        } else {
            const std::string& in_the_way = kMembers[s.next() % kMembers.size()];
            const bool existed = fs::exists(dir / in_the_way);
            if (!existed) fs::create_directory(dir / in_the_way);
            bool threw = false;
            {
                woven::io::OutputSet set(dir.string(), kMembers);
                dead_temporaries = false;
                stage(set, files);
                try {
                    set.publish(kManifest, nlohmann::json{{"files", set.files_json()}}.dump());
                } catch (const woven::RuntimeError& e) {
                    woven::fuzz::check_one_line(e.what());
                    threw = true;
                }
            }
            if (!existed) {
                woven::fuzz::require(threw, "publish (over a directory it must refuse)");
                fs::remove(dir / in_the_way);
            } else {
                published = files;  // the member was a file of the last set: nothing in the way
                any = true;
            }
        }
        check_folder(dir, any ? &published : nullptr, dead_temporaries);
    }
    fs::remove_all(dir, ec);
    return 0;
}
