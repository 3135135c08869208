// libFuzzer target: the JSON files an output folder holds, read back by check, report and sweep
// (io::read_output_json): a manifest (report.json, cusick.json, kes-report.json), a point.json
// and a sweep.json. The first byte picks which; the rest is written as that file into a folder
// and read back as the commands read it. Bad input must be a one-line InputError; an accepted
// document must be nested at most kMaxOutputJsonDepth deep, and walk and dump without a crash.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include <unistd.h>

#include "fuzz_support.hpp"
#include "woven/common/error.hpp"
#include "woven/io/output_file.hpp"

namespace {

/// Depth of a parsed document (the reader's limit must hold), iteratively.
int depth_of(const nlohmann::json& j)
{
    int deepest = 0;
    std::vector<std::pair<const nlohmann::json*, int>> todo{{&j, 0}};
    while (!todo.empty()) {
        auto [n, d] = todo.back();
        todo.pop_back();
        if (n->is_structured()) {
            deepest = std::max(deepest, d + 1);
            for (const auto& c : *n) todo.push_back({&c, d + 1});
        }
    }
    return deepest;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    using namespace woven;
    static const std::filesystem::path dir = [] {
        const auto d = std::filesystem::temp_directory_path() / ("woven_fuzz_output_json_" + std::to_string(::getpid()));
        std::filesystem::create_directories(d);
        return d;
    }();
    if (size == 0) return 0;
    static const char* const names[] = {"report.json", "cusick.json", "kes-report.json", "point.json", "sweep.json"};
    const char* name = names[data[0] % 5];
    const std::size_t limit = data[0] % 5 == 4 ? io::kMaxSweepTableBytes : io::kMaxManifestBytes;
    const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
    const std::filesystem::path file = dir / name;
    {
        std::ofstream out(file, std::ios::binary | std::ios::trunc);
        out.write(text.data(), static_cast<std::streamsize>(text.size()));
    }
    nlohmann::json j;
    try {
        j = io::read_output_json(file.string(), limit, "a file woven wrote");
    } catch (const InputError& e) {
        woven::fuzz::check_one_line(e.what());
        return 0;
    }
    woven::fuzz::require(depth_of(j) <= io::kMaxOutputJsonDepth, "document (nested deeper than the limit)");
    // What the readers do with it: look up the manifest's files, dump it again.
    if (j.is_object() && j.contains("files")) {
        const auto& f = j["files"];
        if (f.is_object())
            for (auto it = f.begin(); it != f.end(); ++it) (void)it.key().size();
    }
    (void)j.dump(2);
    return 0;
}
