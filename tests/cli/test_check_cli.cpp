// `woven check FILE|DIR...`: the commands' readers and messages without a simulation, and
// finished output folders against their manifests.
#include <filesystem>
#include <string>

#include <sys/stat.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli/cli_support.hpp"
#include "woven/io/sha256.hpp"

namespace fs = std::filesystem;
using woven::test::kTinyScene;
using woven::test::Outcome;
using woven::test::replace;
using woven::test::slurp;
using woven::test::write;

namespace {

const std::string kSource = WOVEN_SOURCE_DIR;

/// The lines of `s`.
std::vector<std::string> lines(const std::string& s)
{
    std::vector<std::string> out;
    std::size_t a = 0;
    for (std::size_t b; (b = s.find('\n', a)) != std::string::npos; a = b + 1) out.push_back(s.substr(a, b - a));
    return out;
}

}  // namespace

class Check : public woven::test::WovenProcessTest {
protected:
    /// A finished drape folder `res` of the tiny scene (a few steps, no picture).
    void drape()
    {
        write(dir_ / "tiny.toml", kTinyScene);
        const Outcome r = woven("drape tiny.toml --out res --max-steps 10 --no-render --threads 1");
        ASSERT_EQ(r.code, 0) << r.err;
    }
};

TEST_F(Check, HelpAndTheBuiltInFilesPass)
{
    const Outcome h = woven("check --help");
    EXPECT_EQ(h.code, 0);
    EXPECT_NE(h.out.find("Usage"), std::string::npos);
    const Outcome r = woven("check " + kSource + "/fabrics/cotton.toml " + kSource + "/scenes/cube.toml " + kSource +
                            "/scenes/chair.toml " + kSource + "/assets/chair.obj");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    ASSERT_EQ(lines(r.out).size(), 4u) << r.out;
    EXPECT_NE(r.out.find("cotton.toml: ok (fabric cotton)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("cube.toml: ok (scene cube, 51 x 51 particles, 2 obstacles, fabric cotton)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("chair.obj: ok (mesh,"), std::string::npos) << r.out;
}

TEST_F(Check, BadFilesGetTheCommandsOwnMessages)
{
    // A fabric: the message `woven fit` gives for the same file.
    write(dir_ / "bad-fabric.toml", replace(slurp(kSource + "/fabrics/cotton.toml"), "areal_density_mg_cm2 = 12.0", "areal_density_mg_cm2 = -1"));
    const Outcome fit = woven("fit bad-fabric.toml --out f");
    const Outcome c1 = woven("check bad-fabric.toml");
    EXPECT_EQ(fit.code, 2);
    EXPECT_EQ(c1.code, 2);
    EXPECT_EQ(c1.err, fit.err);
    EXPECT_NE(c1.err.find("bad-fabric.toml: areal_density_mg_cm2:"), std::string::npos) << c1.err;
    // A scene: the message `woven drape` gives; an unknown key: its warning, and exit 0.
    write(dir_ / "bad-scene.toml", replace(kTinyScene, "type = \"sphere\"", "type = \"cone\""));
    const Outcome drape = woven("drape bad-scene.toml --out d");
    const Outcome c2 = woven("check bad-scene.toml");
    EXPECT_EQ(drape.code, 2);
    EXPECT_EQ(c2.code, 2);
    EXPECT_EQ(c2.err, drape.err);
    write(dir_ / "odd-scene.toml", replace(kTinyScene, "height_m = 0.12", "height_m = 0.12\ncolour = 3"));
    const Outcome c3 = woven("check odd-scene.toml");
    EXPECT_EQ(c3.code, 0) << c3.err;
    EXPECT_NE(c3.err.find("woven: warning: odd-scene.toml:"), std::string::npos) << c3.err;
    EXPECT_NE(c3.err.find("cloth.colour: unknown key"), std::string::npos) << c3.err;
    // A scene whose fabric file is bad: the fabric's message.
    write(dir_ / "uses-bad.toml", replace(kTinyScene, "fabric = \"cotton\"", "fabric = \"bad-fabric.toml\""));
    const Outcome c4 = woven("check uses-bad.toml");
    EXPECT_EQ(c4.code, 2);
    EXPECT_NE(c4.err.find("bad-fabric.toml: areal_density_mg_cm2:"), std::string::npos) << c4.err;
    // A mesh with a non-number; a missing path; an unknown kind: one line each, all reported.
    write(dir_ / "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n");
    write(dir_ / "notes.txt", "hello\n");
    const Outcome c5 = woven("check bad.obj nothere.toml notes.txt " + kSource + "/fabrics/silk.toml");
    EXPECT_EQ(c5.code, 2);
    const auto err = lines(c5.err);
    ASSERT_EQ(err.size(), 3u) << c5.err;
    EXPECT_EQ(err[0].rfind("woven: error: bad.obj:3: v:", 0), 0u) << err[0];
    EXPECT_EQ(err[1], "woven: error: nothere.toml: file: no such file or folder");
    EXPECT_EQ(err[2], "woven: error: notes.txt: file: expected a fabric or scene .toml, an .obj mesh or an output folder");
    EXPECT_NE(c5.out.find("silk.toml: ok (fabric silk)"), std::string::npos) << c5.out;
    // A FIFO named like a TOML file: refused as the commands refuse it, not read (a read would block).
    ASSERT_EQ(::mkfifo((dir_ / "pipe.toml").c_str(), 0600), 0);
    const Outcome c6 = woven("check pipe.toml");
    EXPECT_EQ(c6.code, 2);
    EXPECT_EQ(c6.err, "woven: error: pipe.toml: file: is not a regular file (a device, FIFO or socket); expected a fabric or scene .toml file\n");
}

TEST_F(Check, AFinishedFolderPassesAndEachDamageIsFound)
{
    drape();
    const Outcome ok = woven("check res");
    EXPECT_EQ(ok.code, 0) << ok.err;
    EXPECT_NE(ok.out.find("res: ok (output of drape or fit, 3 files listed in report.json)"), std::string::npos) << ok.out;

    // A changed file, a removed one, and a non-finite number in the report: one line each.
    write(dir_ / "res" / "drape.obj", slurp(dir_ / "res" / "drape.obj") + "# edited\n");
    fs::remove(dir_ / "res" / "drape.ply");
    auto j = nlohmann::json::parse(slurp(dir_ / "res" / "report.json"));
    j["energy"]["total_J"] = nullptr;
    write(dir_ / "res" / "report.json", j.dump(2));
    const Outcome bad = woven("check res");
    EXPECT_EQ(bad.code, 2);
    const auto err = lines(bad.err);
    ASSERT_EQ(err.size(), 3u) << bad.err;
    EXPECT_NE(bad.err.find("res/drape.obj: bytes: "), std::string::npos) << bad.err;
    EXPECT_NE(bad.err.find("res/drape.ply: file: listed in res/report.json but missing"), std::string::npos) << bad.err;
    EXPECT_NE(bad.err.find("res/report.json: energy.total_J: not a finite number"), std::string::npos) << bad.err;

    // The same size, other bytes: the checksum finds it.
    drape();
    std::string obj = slurp(dir_ / "res" / "drape.obj");
    obj[obj.size() - 2] = obj[obj.size() - 2] == '1' ? '2' : '1';
    write(dir_ / "res" / "drape.obj", obj);
    const Outcome sum = woven("check res");
    EXPECT_EQ(sum.code, 2);
    EXPECT_NE(sum.err.find("res/drape.obj: sha256: differs from res/report.json's"), std::string::npos) << sum.err;

    // A report that does not parse; a folder with no manifest.
    write(dir_ / "res" / "report.json", "{\"energy\": NaN}");
    const Outcome nan = woven("check res");
    EXPECT_EQ(nan.code, 2);
    EXPECT_NE(nan.err.find("res/report.json: json: expected the manifest a woven command wrote (not JSON: syntax error at byte"), std::string::npos) << nan.err;
    fs::remove(dir_ / "res" / "report.json");
    const Outcome none = woven("check res");
    EXPECT_EQ(none.code, 2);
    EXPECT_EQ(none.err, "woven: error: res: manifest: no report.json, cusick.json, kes-report.json, sweep.json or an experiment's "
              "cube_results.json, corner_map.json or figure1.json (not a finished woven output folder)\n");
}

TEST_F(Check, AGlbThatDoesNotLoadIsFoundEvenWithItsChecksumInTheManifest)
{
    drape();
    const std::string broken = slurp(dir_ / "res" / "drape.glb").substr(0, 100);
    write(dir_ / "res" / "drape.glb", broken);
    auto j = nlohmann::json::parse(slurp(dir_ / "res" / "report.json"));
    j["files"]["drape.glb"] = {{"bytes", broken.size()}, {"sha256", woven::io::sha256_hex(broken)}};
    write(dir_ / "res" / "report.json", j.dump(2));
    const Outcome r = woven("check res");
    EXPECT_EQ(r.code, 2);
    EXPECT_EQ(r.err.rfind("woven: error: res/drape.glb: glb: does not load as glTF 2.0 binary", 0), 0u) << r.err;
    EXPECT_EQ(lines(r.err).size(), 1u) << r.err;
}
