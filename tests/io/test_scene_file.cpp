#include <algorithm>
// Scene files: built-in scenes, error messages, overrides; OBJ mesh loading.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "woven/common/error.hpp"
#include "woven/geometry/mesh_ops.hpp"
#include "woven/io/embedded_data.hpp"
#include "woven/io/mesh_file.hpp"
#include "woven/io/scene_file.hpp"

namespace fs = std::filesystem;
using namespace woven;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

namespace {

const std::string kSource = "test.toml";

/// 1-based line of the first occurrence of `needle` in `text`.
int line_of(const std::string& text, const std::string& needle)
{
    const auto at = text.find(needle);
    return at == std::string::npos ? -1 : 1 + static_cast<int>(std::count(text.begin(), text.begin() + at, '\n'));
}

/// A valid scene with a cloth and one box; `extra` is appended.
std::string cube_scene(const std::string& cloth_extra = "", const std::string& extra = "")
{
    return "name = \"t\"\n[cloth]\nsize_m = [1.0, 1.0]\ngrid = [11, 11]\nheight_m = 0.51\n" + cloth_extra +
           "\n[[obstacle]]\ntype = \"plane\"\n\n[[obstacle]]\ntype = \"box\"\ncentre_m = [0, 0, 0.25]\nsize_m = [0.5, 0.5, 0.5]\n" +
           extra;
}

/// The InputError message of parsing `text`, or "" if it parsed.
std::string error_of(const std::string& text, const std::string& base_dir = ".")
{
    try {
        io::parse_scene(text, kSource, base_dir);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

fs::path temp_dir(const std::string& name)
{
    const fs::path d = fs::temp_directory_path() / ("woven_test_scene_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

}  // namespace

// ---- built-in scenes ----

TEST(BuiltinScenes, NamesAreSorted)
{
    const auto names = io::builtin_scene_names();
    EXPECT_THAT(names, ElementsAre("chair", "cube", "drape_tester", "sphere", "table"));
}

TEST(BuiltinScenes, CubeIsThePapersExperiment)
{
    const io::SceneSpec s = io::find_scene("cube");
    EXPECT_EQ(s.name, "cube");
    EXPECT_EQ(s.cloth.nu, 51);
    EXPECT_EQ(s.cloth.nv, 51);
    EXPECT_NEAR(s.cloth.sigma(), 0.02, 1e-12);
    EXPECT_NEAR(s.cloth.centre.z(), 0.51, 1e-12);
    EXPECT_THAT(s.obstacle_kinds, ElementsAre("plane", "box"));
    ASSERT_EQ(s.obstacles.size(), 2u);
    EXPECT_EQ(s.obstacles[1].kind(), "box");
    EXPECT_NEAR(s.obstacles[1].distance(Vec3(0, 0, 0.6)), 0.1, 1e-12);  // cube top at 0.5 m
    EXPECT_NEAR(s.obstacles[0].distance(Vec3(2, 2, 0.3)), 0.3, 1e-12);  // floor at z = 0
    EXPECT_EQ(s.fabric, "cotton");
    EXPECT_TRUE(s.camera.given);
    EXPECT_TRUE(s.pinned_indices().empty());
    EXPECT_EQ(s.cloth.initial_positions().size(), 51u * 51u);
}

TEST(BuiltinScenes, TableSphereDrapeTesterChair)
{
    const io::SceneSpec table = io::find_scene("table");
    EXPECT_THAT(table.obstacle_kinds, ElementsAre("plane", "disc", "cylinder", "disc"));
    EXPECT_EQ(table.obstacles[1].kind(), "cylinder");  // a disc is a short cylinder
    EXPECT_NEAR(table.obstacles[1].distance(Vec3(0, 0, 0.6)), 0.05, 1e-9);  // top at 0.55 m
    EXPECT_NEAR(table.cloth.sigma(), 0.02, 1e-12);

    const io::SceneSpec sphere = io::find_scene("sphere");
    EXPECT_THAT(sphere.obstacle_kinds, ElementsAre("plane", "sphere"));
    EXPECT_NEAR(sphere.obstacles[1].distance(Vec3(0, 0, 0.6)), 0.1, 1e-12);
    EXPECT_NEAR(sphere.cloth.sigma(), 0.02, 1e-12);

    const io::SceneSpec tester = io::find_scene("drape_tester");
    EXPECT_THAT(tester.obstacle_kinds, ElementsAre("plane", "disc", "cylinder"));
    EXPECT_EQ(tester.cloth.nu, 31);
    EXPECT_NEAR(tester.cloth.size_u, 0.30, 1e-12);
    EXPECT_NEAR(tester.cloth.sigma(), 0.01, 1e-12);
    EXPECT_THAT(tester.description, HasSubstr("square"));
    // 18 cm diameter disc: the rim is 9 cm from the axis.
    EXPECT_NEAR(tester.obstacles[1].distance(Vec3(0.10, 0, 0.199)), 0.01, 1e-9);

    const io::SceneSpec chair = io::find_scene("chair");
    EXPECT_THAT(chair.obstacle_kinds, ElementsAre("plane", "mesh"));
    EXPECT_EQ(chair.obstacles[1].kind(), "mesh");
    EXPECT_NEAR(chair.cloth.size_u, 1.2, 1e-12);
    EXPECT_NEAR(chair.cloth.sigma(), 0.02, 1e-12);
    const auto b = chair.obstacles[1].bounds();
    EXPECT_NEAR(b.hi.z(), 0.80, 1e-6);
    EXPECT_GT(chair.cloth.centre.z(), b.hi.z());
}

TEST(BuiltinScenes, SceneFilesOnDiskMatchTheEmbeddedOnes)
{
    for (const auto& name : io::builtin_scene_names()) {
        const std::string path = std::string(WOVEN_SOURCE_DIR) + "/scenes/" + name + ".toml";
        std::vector<std::string> warnings;
        const io::SceneSpec s = io::load_scene(path, &warnings);  // resolves ../assets/chair.obj on disk
        EXPECT_TRUE(warnings.empty()) << name << ": " << (warnings.empty() ? "" : warnings.front());
        EXPECT_EQ(s.name, name);
        EXPECT_EQ(s.obstacles.size(), io::find_scene(name).obstacles.size());
    }
}

TEST(BuiltinScenes, FindSceneByPathAndUnknownName)
{
    const io::SceneSpec s = io::find_scene(std::string(WOVEN_SOURCE_DIR) + "/scenes/sphere.toml");
    EXPECT_EQ(s.name, "sphere");
    try {
        io::find_scene("no_such_scene");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_THAT(std::string(e.what()), HasSubstr("no_such_scene"));
        EXPECT_THAT(std::string(e.what()), HasSubstr("cube"));
    }
}

// ---- parsing details ----

TEST(SceneFile, DefaultsAndAllSections)
{
    const std::string text = cube_scene("rotation_deg = 30\npinned = [[0, 0], [10, 0]]\nclamped_edges = [\"j1\"]\n",
                                        "[solver]\nkind = \"paper\"\nseed = 7\nmax_steps = 100\nresidual_tolerance = 0.01\n"
                                        "move_tolerance_m = 1e-6\ntime_step_s = 0.01\ncontact_distance_m = 0.002\n"
                                        "viscosity_per_s = 1.5\nfriction = 0.4\nthreads = 2\ncreep_softening = 1\nfall_duration_s = 1.5\n"
                                        "[model]\nbending_form = \"work\"\nshear_law = \"measured\"\ngram_force = \"standard\"\ngravity_m_s2 = 9.81\nC0_J = 0.5\n"
                                        "[camera]\neye_m = [1, 2, 3]\ntarget_m = [0, 0, 0]\nfov_deg = 40\n");
    std::vector<std::string> warnings;
    const io::SceneSpec s = io::parse_scene(text, kSource, ".", &warnings);
    EXPECT_TRUE(warnings.empty());
    EXPECT_NEAR(s.cloth.sigma(), 0.1, 1e-12);
    EXPECT_NEAR(s.cloth.yaw_deg, 30, 1e-12);
    EXPECT_EQ(s.solver.kind, sim::SolverKind::PAPER);
    EXPECT_EQ(s.solver.seed, 7u);
    EXPECT_EQ(s.solver.max_steps, 100);
    EXPECT_DOUBLE_EQ(s.solver.residual_tolerance, 0.01);
    EXPECT_DOUBLE_EQ(s.solver.move_tolerance, 1e-6);
    EXPECT_DOUBLE_EQ(s.solver.time_step, 0.01);
    EXPECT_DOUBLE_EQ(s.solver.contact_distance, 0.002);
    EXPECT_DOUBLE_EQ(s.solver.viscosity, 1.5);
    EXPECT_DOUBLE_EQ(s.solver.friction, 0.4);
    EXPECT_EQ(s.solver.threads, 2);
    EXPECT_DOUBLE_EQ(s.solver.fast.creep_softening, 1.0);  // the continuation off
    EXPECT_DOUBLE_EQ(s.solver.fast.fall_duration, 1.5);
    EXPECT_EQ(s.model.bending_form, model::BendingForm::WORK);
    EXPECT_EQ(s.model.shear_law, model::ShearLaw::MEASURED);
    EXPECT_EQ(s.model.gram_force, units::GramForce::STANDARD);
    EXPECT_DOUBLE_EQ(s.model.gravity, 9.81);
    EXPECT_DOUBLE_EQ(s.model.C0, 0.5);
    EXPECT_TRUE(s.camera.given);
    EXPECT_DOUBLE_EQ(s.camera.fov_deg, 40);
    // Pinned (0,0), (10,0) and the whole j = 10 edge: 2 + 11 particles.
    const auto pins = s.pinned_indices();
    EXPECT_EQ(pins.size(), 13u);
    EXPECT_EQ(pins.front(), 0);
    EXPECT_EQ(pins[1], 10);
    EXPECT_EQ(pins[2], 110);
    EXPECT_EQ(pins.back(), 120);
}

TEST(SceneFile, MinimalSceneUsesDefaults)
{
    const io::SceneSpec s = io::parse_scene("name = \"empty\"\n", "empty.toml", ".");
    EXPECT_EQ(s.name, "empty");
    EXPECT_EQ(s.cloth.nu, 51);
    EXPECT_NEAR(s.cloth.sigma(), 0.02, 1e-12);
    EXPECT_TRUE(s.obstacles.empty());
    EXPECT_EQ(s.solver.kind, sim::SolverKind::FAST);
    EXPECT_EQ(s.model.shear_law, model::ShearLaw::DEEMBEDDED);
    EXPECT_FALSE(s.camera.given);
}

TEST(SceneFile, UnknownKeysAreWarningsNotErrors)
{
    std::vector<std::string> warnings;
    const io::SceneSpec s = io::parse_scene(cube_scene("colour = \"red\"\n", "[solver]\nspeed = 3\n") + "\nextra = 1\n",
                                            kSource, ".", &warnings);
    EXPECT_EQ(s.obstacles.size(), 2u);
    ASSERT_EQ(warnings.size(), 3u);
    std::string all;
    for (const auto& w : warnings) all += w + "\n";
    EXPECT_THAT(all, HasSubstr("test.toml:" + std::to_string(line_of(cube_scene("colour = \"red\"\n"), "colour")) +
                               ": cloth.colour: unknown key, ignored"));
    EXPECT_THAT(all, HasSubstr("solver.speed"));
    EXPECT_THAT(all, HasSubstr("extra"));
}

TEST(SceneFile, FabricPathResolvesAgainstTheSceneFolder)
{
    EXPECT_EQ(io::parse_scene("[cloth]\nfabric = \"wool\"\n", kSource, "/data/scenes").fabric, "wool");
    EXPECT_EQ(io::parse_scene("[cloth]\nfabric = \"my.toml\"\n", kSource, "/data/scenes").fabric, "/data/scenes/my.toml");
    EXPECT_EQ(io::parse_scene("fabric = \"../f/x.toml\"\n", kSource, "/data/scenes").fabric, "/data/f/x.toml");
}

TEST(SceneFile, DiscIsAThinCylinderBelowItsTopCentre)
{
    const io::SceneSpec s = io::parse_scene(
        "[cloth]\nheight_m = 1.0\n[[obstacle]]\ntype = \"disc\"\ncentre_m = [0, 0, 0.5]\nradius_m = 0.2\n", kSource, ".");
    ASSERT_EQ(s.obstacles.size(), 1u);
    EXPECT_NEAR(s.obstacles[0].distance(Vec3(0, 0, 0.6)), 0.1, 1e-12);
    EXPECT_NEAR(s.obstacles[0].distance(Vec3(0, 0, 0.4)), 0.097, 1e-12);  // default thickness 3 mm
}

TEST(SceneFile, MeshFileRelativeToTheSceneAndEmbeddedFallback)
{
    const fs::path d = temp_dir("mesh");
    fs::copy_file(fs::path(WOVEN_SOURCE_DIR) / "assets" / "chair.obj", d / "c.obj");
    const std::string scene =
        "[cloth]\nsize_m = [1.2, 1.2]\ngrid = [13, 13]\nheight_m = 1.5\n[[obstacle]]\ntype = \"mesh\"\nfile = \"FILE\"\n"
        "scale = 0.5\ntranslate_m = [0, 0, 0.1]\n";
    auto with = [&](const std::string& f) { return std::string(scene).replace(scene.find("FILE"), 4, f); };
    const io::SceneSpec a = io::parse_scene(with("c.obj"), kSource, d.string());
    EXPECT_NEAR(a.obstacles[0].bounds().hi.z(), 0.5, 1e-6);  // 0.8 * 0.5 + 0.1
    EXPECT_NEAR(a.obstacles[0].bounds().lo.z(), 0.1, 1e-6);
    // Not on disk next to the scene: "assets/chair.obj" is the embedded asset.
    const io::SceneSpec b = io::parse_scene(with("assets/chair.obj"), kSource, d.string());
    EXPECT_EQ(b.obstacle_kinds.front(), "mesh");
    // A broken mesh file: the error names the scene, the field and the mesh file.
    write(d / "empty.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    const std::string what = error_of(with("empty.obj"), d.string());
    EXPECT_THAT(what, HasSubstr("test.toml: obstacle[1].file: "));
    EXPECT_THAT(what, HasSubstr("empty.obj: faces"));
    fs::remove_all(d);
}

// ---- errors: each names the file and the field ----

struct ErrorCase {
    const char* name;
    std::string text;
    std::vector<std::string> expected;  ///< substrings of the message
};

void PrintTo(const ErrorCase& c, std::ostream* os) { *os << c.name; }

class SceneErrors : public ::testing::TestWithParam<ErrorCase> { };

TEST_P(SceneErrors, ThrowInputErrorNamingFileAndField)
{
    const ErrorCase& c = GetParam();
    const std::string what = error_of(c.text);
    ASSERT_FALSE(what.empty()) << c.name << ": parsed without error";
    EXPECT_THAT(what, HasSubstr("test.toml")) << what;
    for (const auto& e : c.expected) EXPECT_THAT(what, HasSubstr(e)) << c.name;
    EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
}

INSTANTIATE_TEST_SUITE_P(
    SceneFile, SceneErrors,
    ::testing::Values(
        ErrorCase{"Syntax", "name = \"x\"\n[cloth\nsize_m = 1\n", {"test.toml:2:", "TOML syntax"}},
        ErrorCase{"UnknownObstacleType", cube_scene("", "[[obstacle]]\ntype = \"cone\"\n"),
                  {"obstacle[3].type", "unknown obstacle type \"cone\""}},
        ErrorCase{"MissingType", cube_scene("", "[[obstacle]]\ncentre_m = [0, 0, 0]\n"), {"obstacle[3].type", "missing"}},
        ErrorCase{"MissingRadius", cube_scene("", "[[obstacle]]\ntype = \"sphere\"\ncentre_m = [2, 2, 0.2]\n"),
                  {"obstacle[3].radius_m", "missing"}},
        ErrorCase{"WrongTypeString", "[cloth]\nsize_m = \"big\"\n", {"cloth.size_m", "array of 2 numbers"}},
        ErrorCase{"WrongTypeNumber", "[cloth]\nheight_m = \"high\"\n", {"cloth.height_m", "expected a number"}},
        ErrorCase{"WrongArrayLength", cube_scene("", "[[obstacle]]\ntype = \"box\"\ncentre_m = [2, 2]\nsize_m = [1, 1, 1]\n"),
                  {"obstacle[3].centre_m", "array of 3 numbers"}},
        ErrorCase{"WrongTypeTable", "cloth = 3\n", {"cloth", "table"}},
        ErrorCase{"NotFiniteNan", "[cloth]\nheight_m = nan\n", {"cloth.height_m", "finite"}},
        ErrorCase{"NotFiniteInf", cube_scene("", "[[obstacle]]\ntype = \"sphere\"\ncentre_m = [inf, 0, 0]\nradius_m = 1\n"),
                  {"obstacle[3].centre_m", "finite"}},
        ErrorCase{"NegativeBoxSize", cube_scene("", "[[obstacle]]\ntype = \"box\"\ncentre_m = [3, 3, 0.2]\nsize_m = [1, -1, 1]\n"),
                  {"obstacle[3].size_m", "positive"}},
        ErrorCase{"ZeroRadius", cube_scene("", "[[obstacle]]\ntype = \"sphere\"\ncentre_m = [3, 3, 0]\nradius_m = 0\n"),
                  {"obstacle[3].radius_m", "positive"}},
        ErrorCase{"NegativeFriction", "[solver]\nfriction = -0.2\n", {"solver.friction", "-0.2"}},
        ErrorCase{"CreepSofteningBelowOne", "[solver]\ncreep_softening = 0.5\n", {"solver.creep_softening", "0.5"}},
        ErrorCase{"CreepSofteningTooLarge", "[solver]\ncreep_softening = 1e5\n", {"solver.creep_softening", "100000"}},
        ErrorCase{"NegativeClothSize", "[cloth]\nsize_m = [-1.0, 1.0]\n", {"cloth.size_m", "positive"}},
        ErrorCase{"ZeroCylinderHeight",
                  cube_scene("", "[[obstacle]]\ntype = \"cylinder\"\nbase_m = [3, 3, 0]\nradius_m = 0.1\nheight_m = 0\n"),
                  {"obstacle[3].height_m", "positive"}},
        ErrorCase{"ZeroNormal", "[[obstacle]]\ntype = \"plane\"\nnormal = [0, 0, 0]\n", {"obstacle[1].normal", "non-zero"}},
        ErrorCase{"SigmaMismatch", "[cloth]\nsize_m = [1.0, 2.0]\ngrid = [51, 51]\n", {"cloth.size_m, cloth.grid", "spacing"}},
        ErrorCase{"GridTooSmall", "[cloth]\ngrid = [2, 2]\nsize_m = [1, 1]\n", {"cloth.grid", "at least 3"}},
        ErrorCase{"GridTooLarge", "[cloth]\ngrid = [3000, 3000]\nsize_m = [1, 1]\n", {"cloth.grid", "too large"}},
        ErrorCase{"GridNotInteger", "[cloth]\ngrid = [51.5, 51]\n", {"cloth.grid", "integer"}},
        ErrorCase{"PinnedOutOfRange", cube_scene("pinned = [[0, 0], [11, 0]]\n"), {"cloth.pinned[2]", "expected an integer in [0, 10], got 11"}},
        ErrorCase{"PinnedNegative", cube_scene("pinned = [[0, -1]]\n"), {"cloth.pinned[1]", "expected an integer in [0, 10], got -1"}},
        ErrorCase{"BadClampedEdge", cube_scene("clamped_edges = [\"k0\"]\n"), {"cloth.clamped_edges"}},
        ErrorCase{"MissingMeshFile", "[[obstacle]]\ntype = \"mesh\"\nfile = \"no_such_chair.obj\"\n",
                  {"obstacle[1].file", "no_such_chair.obj"}},
        ErrorCase{"ClothInsideBox",
                  "[cloth]\nheight_m = 0.4\n[[obstacle]]\ntype = \"plane\"\n[[obstacle]]\ntype = \"box\"\ncentre_m = [0, 0, 0.25]\nsize_m = [0.5, 0.5, 0.5]\n",
                  {"cloth", "obstacle[2] (box)", "inside or touching"}},
        ErrorCase{"ClothTouchingBox",
                  "[cloth]\nheight_m = 0.5\n[[obstacle]]\ntype = \"box\"\ncentre_m = [0, 0, 0.25]\nsize_m = [0.5, 0.5, 0.5]\n",
                  {"cloth", "obstacle[1] (box)"}},
        ErrorCase{"ClothBelowFloor", "[cloth]\nheight_m = -0.1\n[[obstacle]]\ntype = \"plane\"\n", {"cloth", "obstacle[1] (plane)"}},
        ErrorCase{"ClothThroughSphere",
                  "[cloth]\nheight_m = 0.2\n[[obstacle]]\ntype = \"sphere\"\ncentre_m = [0.3, 0.3, 0.25]\nradius_m = 0.1\n",
                  {"cloth", "obstacle[1] (sphere)"}},
        ErrorCase{"BadSolverKind", "[solver]\nkind = \"slow\"\n", {"solver.kind", "\"fast\""}},
        ErrorCase{"NegativeSeed", "[solver]\nseed = -1\n", {"solver.seed"}},
        ErrorCase{"BadBendingForm", "[model]\nbending_form = \"cubic\"\n", {"model.bending_form"}},
        ErrorCase{"BadShearLaw", "[model]\nshear_law = \"raw\"\n", {"model.shear_law"}},
        ErrorCase{"CameraMissingEye", "[camera]\ntarget_m = [0, 0, 0]\n", {"camera.eye_m", "missing"}},
        ErrorCase{"CameraFov", "[camera]\neye_m = [1, 1, 1]\ntarget_m = [0, 0, 0]\nfov_deg = 190\n", {"camera.fov_deg"}},
        ErrorCase{"ObstacleNotArrayOfTables", "[obstacle]\ntype = \"box\"\n", {"obstacle", "[[obstacle]]"}}),
    [](const ::testing::TestParamInfo<ErrorCase>& info) { return std::string(info.param.name); });

TEST(SceneFile, MissingSceneFileNamesIt)
{
    try {
        io::load_scene("/no/such/dir/scene.toml");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_THAT(std::string(e.what()), HasSubstr("/no/such/dir/scene.toml"));
    }
}

TEST(SceneFile, SyntaxErrorInAFileGivesFileLineColumn)
{
    const fs::path d = temp_dir("syntax");
    write(d / "bad.toml", "name = \"bad\"\n\n[cloth]\nsize_m = [1.0, 1.0\n");
    try {
        io::load_scene((d / "bad.toml").string());
        FAIL();
    } catch (const InputError& e) {
        EXPECT_THAT(std::string(e.what()), HasSubstr((d / "bad.toml").string() + ":"));
        EXPECT_THAT(std::string(e.what()), ::testing::ContainsRegex("bad\\.toml:[45]:[0-9]+: TOML syntax"));
    }
    fs::remove_all(d);
}

// ---- command-line overrides ----

TEST(SceneOverrides, GridKeepsTheClothSize)
{
    io::SceneSpec s = io::find_scene("cube");
    io::SceneOverrides o;
    o.grid = 21;
    o.fabric = "wool";
    o.solver = sim::SolverKind::PAPER;
    o.seed = 42;
    o.max_steps = 10;
    o.threads = 1;
    io::apply_overrides(s, o);
    EXPECT_EQ(s.cloth.nu, 21);
    EXPECT_EQ(s.cloth.nv, 21);
    EXPECT_NEAR(s.cloth.sigma(), 0.05, 1e-12);
    EXPECT_NEAR(s.cloth.size_u, 1.0, 1e-12);
    EXPECT_NEAR(s.cloth.size_v, 1.0, 1e-12);
    EXPECT_EQ(s.fabric, "wool");
    EXPECT_EQ(s.solver.kind, sim::SolverKind::PAPER);
    EXPECT_EQ(s.solver.seed, 42u);
    EXPECT_EQ(s.solver.max_steps, 10);
    EXPECT_EQ(s.solver.threads, 1);

    io::SceneSpec r = io::parse_scene("[cloth]\nsize_m = [1.0, 0.5]\ngrid = [11, 6]\npinned = [[10, 5]]\n", kSource, ".");
    io::SceneOverrides g;
    g.grid = 21;
    io::apply_overrides(r, g);
    EXPECT_EQ(r.cloth.nu, 21);
    EXPECT_EQ(r.cloth.nv, 11);
    EXPECT_NEAR(r.cloth.size_v, 0.5, 1e-12);
    EXPECT_EQ(r.pinned_indices(), std::vector<int>{20 + 21 * 10});

    io::SceneOverrides bad;
    bad.grid = 2;
    EXPECT_THROW(io::apply_overrides(r, bad), InputError);
}

// ---- OBJ meshes ----

TEST(ObjMesh, ChairIsClosedWithDocumentedBounds)
{
    const geometry::TriangleMesh m = io::load_obj_mesh(std::string(WOVEN_SOURCE_DIR) + "/assets/chair.obj");
    EXPECT_GT(m.faces.size(), 100u);
    EXPECT_TRUE(geometry::is_closed(m));
    EXPECT_GT(geometry::signed_volume(m), 0.0);  // outward faces
    // scripts/make_chair.py: 0.80 m wide (x), 0.85 m deep (y), 0.80 m high, standing on z = 0.
    Vec3 lo = m.vertices.front(), hi = lo;
    for (const auto& v : m.vertices) {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
    }
    EXPECT_NEAR(lo.x(), -0.40, 1e-6);
    EXPECT_NEAR(hi.x(), 0.40, 1e-6);
    EXPECT_NEAR(lo.y(), -0.425, 1e-6);
    EXPECT_NEAR(hi.y(), 0.425, 1e-6);
    EXPECT_NEAR(lo.z(), 0.0, 1e-6);
    EXPECT_NEAR(hi.z(), 0.80, 1e-6);
}

TEST(ObjMesh, EmbeddedChairEqualsTheFile)
{
    std::string_view data;
    for (const auto& f : io::data::embedded_files())
        if (f.path == "assets/chair.obj") data = f.data;
    ASSERT_FALSE(data.empty());
    const auto a = io::parse_obj_mesh(data, "assets/chair.obj");
    const auto b = io::load_obj_mesh(std::string(WOVEN_SOURCE_DIR) + "/assets/chair.obj");
    EXPECT_EQ(a.vertices.size(), b.vertices.size());
    EXPECT_EQ(a.faces.size(), b.faces.size());
}

TEST(ObjMesh, QuadsAreTriangulated)
{
    const auto m = io::parse_obj_mesh("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n", "quad.obj");
    EXPECT_EQ(m.vertices.size(), 4u);
    EXPECT_EQ(m.faces.size(), 2u);
}

TEST(ObjMesh, Errors)
{
    auto what = [](auto&& f) -> std::string {
        try {
            f();
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    };
    EXPECT_THAT(what([] { io::load_obj_mesh("/no/such/mesh.obj"); }), HasSubstr("/no/such/mesh.obj: file"));
    EXPECT_THAT(what([] { io::parse_obj_mesh("v 0 0 0\nv 1 0 0\nv 0 1 0\n", "nofaces.obj"); }),
                HasSubstr("nofaces.obj: faces"));
    const std::string bad = what([] { io::parse_obj_mesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "bad.obj"); });
    EXPECT_THAT(bad, HasSubstr("bad.obj"));
    EXPECT_FALSE(bad.empty());
}
