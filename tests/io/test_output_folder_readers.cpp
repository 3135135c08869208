// The readers of what an output folder holds (io/output_file.hpp): regular files only, bounded,
// JSON nested at most 64 deep; the output sets' folder held open and their members removed
// only where the earlier manifest lists them; a glb checked as a viewer reads it; errors
// without a NUL cut.
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/stat.h>
#include <unistd.h>

#include "woven/common/error.hpp"
#include "woven/geometry/triangle_mesh.hpp"
#include "woven/io/output_file.hpp"
#include "woven/io/output_set.hpp"
#include "woven/render/gltf_file.hpp"

namespace fs = std::filesystem;
using namespace woven;
using ::testing::HasSubstr;

namespace {

fs::path fresh_dir(const std::string& name)
{
    const fs::path d = fs::temp_directory_path() / ("woven_outreaders_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

std::string error_of(const std::function<void()>& f)
{
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

std::string slurp(const fs::path& p)
{
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST(OutputFolderReaders, DeepJsonIsRefusedBeforeTheParser)
{
    // 60,000 levels crashed `woven check` (the parser's recursion); 65 is refused, 64 read.
    const std::string deep = std::string(60000, '[') + std::string(60000, ']');
    EXPECT_THAT(error_of([&] { (void)io::parse_output_json(deep, "r.json", "a manifest"); }),
                HasSubstr("r.json: json: expected a manifest nested at most 64 deep"));
    EXPECT_THAT(error_of([&] { (void)io::parse_output_json(std::string(65, '[') + std::string(65, ']'), "r.json", "a manifest"); }),
                HasSubstr("nested at most 64 deep"));
    EXPECT_EQ(io::parse_output_json(std::string(64, '[') + std::string(64, ']'), "r.json", "a manifest").size(), 1u);
    // Brackets inside strings do not count; escaped quotes do not end a string.
    const auto j = io::parse_output_json(R"({"a": "[[[[\"[[[[", "b": [1, 2]})", "r.json", "a manifest", 2);
    EXPECT_EQ(j["b"].size(), 2u);
    EXPECT_EQ(io::json_depth(R"({"a": "[[[[\"[[[[", "b": [1, {"c": []}]})", 100), 4);
    EXPECT_THAT(error_of([&] { (void)io::parse_output_json("{\"a\": 1e3085}", "r.json", "a manifest"); }),
                HasSubstr("r.json: json: expected a manifest (a number out of range)"));
    EXPECT_THAT(error_of([&] { (void)io::parse_output_json("{\"a\": ", "r.json", "a manifest"); }),
                HasSubstr("r.json: json: expected a manifest (not JSON: syntax error at byte"));
}

TEST(OutputFolderReaders, RefuseFifoDeviceAndOversizedFile)
{
    const fs::path d = fresh_dir("fifo");
    ASSERT_EQ(::mkfifo((d / "report.json").c_str(), 0644), 0);
    // Opened without blocking: no writer, yet no hang.
    EXPECT_THAT(error_of([&] { (void)io::read_output_json((d / "report.json").string(), io::kMaxManifestBytes, "a manifest"); }),
                HasSubstr("report.json: file: is not a regular file (a device, FIFO or socket)"));
    fs::create_symlink("/dev/zero", d / "point.json");
    EXPECT_THAT(error_of([&] { (void)io::read_output_json((d / "point.json").string(), io::kMaxManifestBytes, "point.json"); }),
                HasSubstr("point.json: file: is not a regular file"));
    {
        std::ofstream big(d / "big.json", std::ios::binary);
        big << "[";
        big.seekp(static_cast<std::streamoff>(io::kMaxManifestBytes) + 10);
        big << "]";
    }
    EXPECT_THAT(error_of([&] { (void)io::read_output_json((d / "big.json").string(), io::kMaxManifestBytes, "a manifest"); }),
                HasSubstr("expected a manifest of at most 16 MiB, got 16777227 bytes"));
    fs::remove_all(d);
}

TEST(OutputSetPublishing, ASwappedFolderDoesNotRedirectTheSet)
{
    const fs::path d = fresh_dir("swap");
    const fs::path out = d / "out", moved = d / "moved", elsewhere = d / "elsewhere";
    fs::create_directories(out);
    fs::create_directories(elsewhere);
    io::hold_output_dir(out.string());  // as make_output_dir does before the run works
    // While the run works, --out is moved away and a symlink to another folder put in its place.
    fs::rename(out, moved);
    fs::create_directory_symlink(elsewhere, out);
    {
        io::OutputSet set(out.string(), {"a.txt"});
        set.add("a.txt", "a\n");
        nlohmann::json j;
        j["files"] = set.files_json();
        set.publish("report.json", j.dump());
    }
    EXPECT_TRUE(fs::is_empty(elsewhere));
    EXPECT_EQ(slurp(moved / "a.txt"), "a\n");
    EXPECT_TRUE(fs::exists(moved / "report.json"));
    fs::remove_all(d);
}

TEST(OutputSetPublishing, RemovesOnlyWhatTheEarlierManifestLists)
{
    const fs::path d = fresh_dir("own");
    // A file of the user's own with a member's name, in a folder with no earlier set: kept.
    std::ofstream(d / "b.txt") << "mine\n";
    const auto publish = [&](bool with_b) {
        io::OutputSet set(d.string(), {"a.txt", "b.txt"});
        set.add("a.txt", "a\n");
        if (with_b) set.add("b.txt", "b\n");
        nlohmann::json j;
        j["files"] = set.files_json();
        set.publish("report.json", j.dump());
    };
    publish(false);
    EXPECT_EQ(slurp(d / "b.txt"), "mine\n");
    // A set that wrote b.txt, then one that does not: the earlier set's b.txt is removed.
    publish(true);
    EXPECT_EQ(slurp(d / "b.txt"), "b\n");
    publish(false);
    EXPECT_FALSE(fs::exists(d / "b.txt"));
    fs::remove_all(d);
}

TEST(GlbCheck, RefusesWhatAViewerCannotRead)
{
    geometry::TriangleMesh mesh;
    mesh.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0.5)};
    mesh.faces = {Eigen::Vector3i(0, 1, 2), Eigen::Vector3i(1, 3, 2)};
    render::GltfMesh g;
    g.name = "m";
    g.mesh = mesh;
    const std::string glb = render::scene_glb({g});
    ASSERT_EQ(render::check_glb(glb, "x.glb"), 1);
    // The binary chunk holds the indices (uint32) first, then the positions (float); each
    // mutation of its bytes must be refused, as a viewer would fail on it.
    const std::size_t json_len = static_cast<unsigned char>(glb[12]) | static_cast<unsigned char>(glb[13]) << 8 |
                                 static_cast<unsigned char>(glb[14]) << 16;
    const std::size_t bin = 20 + json_len + 8;
    const auto find_u32 = [&](std::uint32_t v, std::size_t from) {
        for (std::size_t k = from; k + 4 <= glb.size(); k += 4) {
            std::uint32_t u;
            std::memcpy(&u, glb.data() + k, 4);
            if (u == v) return k;
        }
        return std::string::npos;
    };
    // An index beyond the vertices.
    std::string bad = glb;
    const std::size_t three = find_u32(3, bin);
    ASSERT_NE(three, std::string::npos);
    const std::uint32_t big = 1000;
    std::memcpy(bad.data() + three, &big, 4);
    EXPECT_THAT(error_of([&] { (void)render::check_glb(bad, "x.glb"); }), HasSubstr("x.glb: glb: mesh 'm' primitive 0: indices: index"));
    // A non-finite position (the 1.0f of a vertex made NaN).
    bad = glb;
    float one = 1.0f;
    std::uint32_t one_bits;
    std::memcpy(&one_bits, &one, 4);
    const std::size_t at = find_u32(one_bits, bin);
    ASSERT_NE(at, std::string::npos);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(bad.data() + at, &nan, 4);
    EXPECT_THAT(error_of([&] { (void)render::check_glb(bad, "x.glb"); }), HasSubstr("POSITION: element"));
    // A position outside the accessor's bounds (1.0 made 2.0).
    bad = glb;
    const float two = 2.0f;
    std::memcpy(bad.data() + at, &two, 4);
    EXPECT_THAT(error_of([&] { (void)render::check_glb(bad, "x.glb"); }), HasSubstr("outside the accessor's min/max"));
    // An accessor that runs past its buffer view: a count raised in the JSON chunk.
    bad = glb;
    const std::size_t c = bad.find("\"count\":4");
    ASSERT_NE(c, std::string::npos);
    bad[c + 8] = '9';
    EXPECT_THAT(error_of([&] { (void)render::check_glb(bad, "x.glb"); }), HasSubstr("x.glb: glb: mesh 'm' primitive 0:"));
    // JSON that does not parse: tinygltf's message spans lines; the error stays one line (fuzz_glb_check).
    bad = glb;
    bad[bad.find("componentType") + 12] = '[';
    const std::string e = error_of([&] { (void)render::check_glb(bad, "x.glb"); });
    EXPECT_THAT(e, HasSubstr("x.glb: glb: does not load as glTF 2.0 binary"));
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

TEST(ErrorMessages, ANulDoesNotCutTheMessage)
{
    const std::string name("a\0b", 3);
    const InputError e("scene '" + name + "'", "name", "expected a name");
    EXPECT_EQ(std::string(e.what()), "scene 'a\\x00b': name: expected a name");
    EXPECT_EQ(std::string(RuntimeError("x " + name + " y").what()), "x a\\x00b y");
}
