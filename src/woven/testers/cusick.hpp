#pragma once
// The Cusick drape tester (BS 5058, ISO 9073-9): a circular specimen clamped centred between
// two horizontal discs on a pedestal, hanging freely around them; its shadow gives the drape
// coefficient and the nodes (analysis/drape_shadow.hpp).
//
//   side view (z up):
//
//          clamp disc (the pinned particles)      specimen: a disc cut from the particle grid
//     ~~~~~~~~~~===========================~~~~~~~~~~   (model/outline.hpp), warp along +y
//     |        ===========================       |      support disc, radius r_d, 3 mm thick,
//     |                    ||                    |      top at disc_top_z
//     |                    || pedestal           |      hanging part: at most R - r_d long
//     |                    ||                    |
//   ======================================================  floor (z = 0), R - r_d + 0.1 m below
//
// Two clamps (CusickClamp): PINNED pins the particles within r_d + clamp_margin sigma of the
// centre at their flat start (the upper disc as a staircase of grid particles); DISCS pins only
// those well inside the disc and holds the ring out to the rim between the support disc and a
// clamp disc of radius r_d, two obstacles whose rims are true circles. In both the hanging part
// meets the support disc's rim as an obstacle.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "woven/analysis/drape_shadow.hpp"
#include "woven/common/choice.hpp"
#include "woven/geometry/obstacle.hpp"
#include "woven/geometry/triangle_mesh.hpp"
#include "woven/kes/fabric.hpp"
#include "woven/model/cloth_model.hpp"
#include "woven/model/outline.hpp"
#include "woven/sim/drape.hpp"

namespace woven::testers {

/// The default particle spacing of the drape tester (m). From 0.5 to 0.25 cm the mean drape
/// coefficient over five seeds moves by 0.3 points (denim, silk; the cotton's several stable
/// drapes by 2.2); 1 cm is too coarse for the soft fabrics (docs/CUSICK.md).
inline constexpr double kCusickDefaultSpacing = 0.005;

/// The clamp: the particles within r_d + this x spacing of the centre are pinned. A grid
/// particle's bending term stands for its sigma-wide dual cell, so pinned rows up to x = r_d +
/// sigma/2 hold the cloth flat up to x = r_d, where the free cloth's first bending cell begins
/// (the instruments' clamp line lies midway between pinned rows for the same reason).
inline constexpr double kCusickClampMargin = 0.5;

/// How the specimen is held on the disc.
enum class CusickClamp {
    PINNED,  ///< the kept particles within r_d + clamp_margin sigma pinned at the flat start
    DISCS,   ///< the particles within r_d - kCusickDiscsPinnedInset sigma pinned; the ring out to r_d held
             ///< by contact between the support disc and a clamp disc of radius r_d (obstacles)
};

/// The clamps' names: "pinned", "discs" (the command line, cusick.json).
inline constexpr std::array<Named<CusickClamp>, 2> kCusickClampNames{{{CusickClamp::PINNED, "pinned"}, {CusickClamp::DISCS, "discs"}}};
/// Its name in kCusickClampNames.
const char* clamp_name(CusickClamp clamp);

/// DISCS: the pinned core ends this many spacings inside the disc's rim; the ring beyond it is
/// held only by the two discs (it keeps the specimen from sliding: the contact has no friction).
inline constexpr double kCusickDiscsPinnedInset = 1.5;

/// DISCS: the default gap between the two discs, in contact distances d^: both barriers hold
/// every particle between them (each at d^/2 from either disc at rest, the weight sagging it
/// by about d^/130).
inline constexpr double kCusickDiscsGap = 1.0;

/// The path the specimen takes to its drape (with friction inside the weave, model::Hysteresis::
/// FRICTION, the drape depends on it).
enum class CusickProtocol {
    /// The clamped specimen starts flat (start_gap_m above the disc, the seeded waviness) and is
    /// released at rest: the overhang falls and swings in the solver's viscous medium, some bends
    /// loading past their rest and unloading, to rest. Today's (and the default).
    RELEASE,
    /// The clamped specimen starts flat with its overhang resting on a horizontal plate, which is
    /// lowered in stages of lower_step_m (each drape to rest, the friction state carried on)
    /// until the hem hangs free, then the plate is taken away and the specimen settles: a
    /// quasi-static, monotonic loading of the bends, as a specimen lowered by hand onto the
    /// disc. The lab's paths lie between the two.
    LOWERED,
};

/// The protocols' names: "release", "lowered" (the command line, cusick.json).
inline constexpr std::array<Named<CusickProtocol>, 2> kCusickProtocolNames{{{CusickProtocol::RELEASE, "release"},
                                                                            {CusickProtocol::LOWERED, "lowered"}}};
/// Its name in kCusickProtocolNames.
const char* protocol_name(CusickProtocol protocol);

/// LOWERED: the smallest automatic plate step (m), 2 spacings at the default spacing.
inline constexpr double kCusickLowerStep = 0.01;

/// A start of the search of rest states (search_cusick): the release from flat (guides 0), or
/// the release onto `guides` guide rods radiating under the overhang, the first at `phase_rad`
/// from the warp towards the weft, which hold the falling overhang up in as many ridges (nodes);
/// once it rests on them they are taken away and it settles to rest on its own.
/// Or (stiffer > 1) the continuation from a stiffer copy of the fabric: its bending curves
/// (warp, weft, bias) times `stiffer` released and draped to rest first, then the fabric itself
/// from there (a stiff fabric folds into fewer nodes; the state keeps them where they are stable).
struct CusickStart {
    int guides = 0;
    double phase_rad = 0;
    double stiffer = 0;
};

/// The instrument's settings (SI).
struct CusickOptions {
    double specimen_diameter_m = 0.30;  ///< the standard's; 0.24 and 0.36 m are also used
    double disc_diameter_m = 0.18;      ///< support (and clamp) disc
    double spacing_m = kCusickDefaultSpacing;
    CusickClamp clamp = CusickClamp::PINNED;
    /// PINNED: the pinned particles reach r_d + this x spacing.
    double clamp_margin = kCusickClampMargin;
    /// DISCS: the gap between the discs (m), at most the contact distance; 0: kCusickDiscsGap d^.
    double clamp_gap_m = 0;
    double disc_thickness_m = 0.003;
    double pedestal_radius_m = 0.015;
    /// Height of the flat start above the support disc's top (m); 0: twice the solver's contact
    /// distance (PINNED), half the gap between the discs (DISCS; there it must be below the gap).
    double start_gap_m = 0;
    /// Largest vertical offset of the seeded start's waviness (m): real specimens never lie
    /// perfectly flat, and a perfectly flat start would drape with the square grid's symmetry.
    /// A smooth function of the rest position (angular modes 1-12 with amplitudes and phases
    /// drawn from solver.seed, mt19937_64, the same on every platform; zero at the disc's edge, full
    /// at the edge), so a seed is the same start at every spacing; it replaces the solver's
    /// per-particle perturbation. 0: none (the solver's perturbation then applies).
    double perturbation_m = 0.001;
    /// The specimen's threads turned about the disc's axis by this angle (degrees, counter-clockwise
    /// seen from above): the whole start turned, the instrument being round. The nodes, r(theta)
    /// and the guide rods' phases stay measured from the warp; the meshes and pictures are in the
    /// instrument's frame.
    double grid_rotation_deg = 0;
    CusickProtocol protocol = CusickProtocol::RELEASE;
    /// LOWERED: the plate's step (m), from the spacing to the overhang; 0: lower_step_m(options).
    double lower_step_m = 0;
    /// After the protocol: this many cycles of a quasi-static vertical shake of the disc, each
    /// a drape to rest at gravity g (1 + shake_amplitude) and one at g (1 - shake_amplitude)
    /// (the clamp's frame, where the disc's acceleration adds to gravity), then a drape to rest
    /// at g. 0: none. With friction the cycles work the bends back and forth inside their loops.
    int shakes = 0;
    double shake_amplitude = 0.5;  ///< the disc's peak acceleration over g, in (0, 1)
    /// A start state replacing the flat one (one position per grid particle, m): a drape read
    /// back (`--start`); the clamp's particles keep the setup's. Empty: the flat start.
    Positions start;
    /// RELEASE: first onto guide rods (CusickStart), then without them.
    CusickStart guides;
    model::ModelOptions model;  ///< its hysteresis: LOADING_BRANCH (default) or FRICTION (the fast solver's)
    sim::SolverOptions solver;  ///< its seed and perturbation make the run-to-run variation
    analysis::DrapeShadowOptions shadow;
};

/// The specimen and the instrument, ready to drape.
struct CusickSetup {
    model::Grid grid;                 ///< covers the specimen and a ring of particles around it
    model::Outline outline;           ///< the specimen's disc
    model::ClothCut cut;              ///< the particles kept, their areas
    std::vector<int> clamped;         ///< the pinned particles (PINNED: within r_d + clamp_margin sigma; DISCS: within r_d - kCusickDiscsPinnedInset sigma)
    std::vector<int> sandwiched;      ///< DISCS: the kept particles held between the discs, not pinned (pinned radius < r <= r_d)
    geometry::ObstacleSet obstacles;  ///< floor, pedestal, support disc; DISCS: and the clamp disc
    Positions initial;                ///< flat, start_gap_m above the disc, perturbed, one per grid particle
    double disc_top_z = 0;            ///< m
    double clamp_radius = 0;          ///< where the held region ends (m): PINNED r_d + clamp_margin sigma, DISCS r_d
    double pinned_radius = 0;         ///< the pinned particles' reach (m): PINNED = clamp_radius, DISCS r_d - kCusickDiscsPinnedInset sigma
    double clamp_disc_bottom_z = 0;   ///< DISCS: the clamp disc's underside (m), clamp_gap_m above disc_top_z
};

/// Builds the instrument (the perturbation drawn from options.solver.seed). Throws InputError("command line", "--specimen-cm" / "--disc-cm" /
/// "--spacing-cm", ...) unless 0 < disc < specimen and the spacing resolves the overhang (at
/// least 2 particles across it and 8 across the specimen).
CusickSetup make_cusick_setup(const CusickOptions& options);

/// LOWERED: the plate's step in force (m): options.lower_step_m, or for 0 the larger of
/// kCusickLowerStep and two spacings, at most the overhang (6 stages on the standard's 30 / 18 cm).
double lower_step_m(const CusickOptions& options);

/// One drape test.
struct CusickResult {
    sim::Result drape;  ///< LOWERED: the last stage's, with steps, iterations and times summed over the stages
    geometry::TriangleMesh surface;  ///< the draped specimen (model::cut_surface)
    std::vector<Vec2> surface_uv;    ///< per surface vertex: rest position in particle spacings (u weft, v warp)
    analysis::DrapeShadow shadow;    ///< DC and nodes, angles from the warp (+y)
    double spacing_m = 0;
    double specimen_area_m2 = 0;  ///< W x this is the specimen's mass
    int particles = 0;            ///< kept particles
    int stages = 1;               ///< drapes run: LOWERED the plate's stages and the settling, guides 2, and 2 per shake and 1 after
};

/// The guide rods: thin cylinders (kGuideRodRadius) from kGuideRodInset beyond the disc's rim
/// to the specimen's radius, kGuideRodDrop below the disc's top at the rim and sloping down at
/// kGuideRodSlopeDeg, at angles phase + 2 pi k / guides.
inline constexpr double kGuideRodRadius = 0.002;    ///< m
inline constexpr double kGuideRodInset = 0.01;      ///< m
inline constexpr double kGuideRodDrop = 0.01;       ///< m
inline constexpr double kGuideRodSlopeDeg = 20.0;   ///< degrees below the horizontal

/// Adds the guide rods of `start` (none for guides 0) to `obstacles`.
void add_guide_rods(geometry::ObstacleSet& obstacles, const CusickOptions& options, double disc_top_z, const CusickStart& start);

/// One rest state the search found.
struct CusickState {
    CusickStart start;
    CusickResult result;
};

/// The search of rest states (a drape has many; the release from flat lands in a high one): the
/// release and one start per guide count, each draped to rest by run_cusick, every state kept. The prediction is the state of lowest energy (docs/CUSICK.md,
/// "The search of rest states": why).
struct CusickSearchOptions {
    bool release = true;     ///< the release from flat is one of the starts
    std::vector<int> modes;  ///< the guide counts (2 for woven cusick --search)
    std::vector<double> stiffer;  ///< the continuations' bending factors (4 and 16 for woven cusick --search)
    int jobs = 1;            ///< starts run at once (each on options.solver.threads threads)
};
struct CusickSearch {
    std::vector<CusickState> states;  ///< in the order of the starts: the release, then the guide counts
    int prediction = -1;              ///< the state of lowest total energy
    bool interrupted = false;
};

/// The phase of the n-guide start of a seed: uniform in [0, 2 pi / n) from (seed, n), mt19937_64.
double guide_phase(std::uint64_t seed, int guides);

/// The fabric with its bending curves (warp, weft and the bias B) times `factor` (> 0).
kes::FabricData stiffer_in_bending(const kes::FabricData& fabric, double factor);

/// Runs the search. `progress` and `iteration` are called from one thread at a time (under a
/// lock with jobs > 1); false from either stops every start.
CusickSearch search_cusick(const kes::FabricData& fabric, const CusickOptions& options, const CusickSearchOptions& search,
                           const sim::ProgressCallback& progress = {}, const sim::IterationCallback& iteration = {});

/// Drapes the specimen to rest by options.protocol (sim::drape with the residual test of `woven
/// drape`; with friction the slip states carried through every step and stage) and reads its
/// shadow. `progress` after each step, `iteration` before each Newton iteration (sim::drape's).
CusickResult run_cusick(const kes::FabricData& fabric, const CusickOptions& options, const sim::ProgressCallback& progress = {},
                        const sim::IterationCallback& iteration = {});

/// One seed's measurement: with `search` the search of rest states (search_cusick), else the
/// drape (run_cusick) as the one state, predicted (prediction -1: a search that reached no rest
/// state).
CusickSearch run_cusick_seed(const kes::FabricData& fabric, const CusickOptions& options, const CusickSearchOptions* search,
                             const sim::ProgressCallback& progress = {}, const sim::IterationCallback& iteration = {});

/// A start's label: "release", "<n> guides", "from <f> x B".
std::string start_name(const CusickStart& start);

/// The statistics of several runs (seeds): the drape coefficient's mean and sample standard
/// deviation (%), and how many runs found each node count.
struct CusickStatistics {
    double drape_coefficient_mean = 0, drape_coefficient_std = 0;
    std::map<int, int> runs_per_node_count;
};
CusickStatistics cusick_statistics(const std::vector<double>& drape_coefficients, const std::vector<int>& node_counts);

}  // namespace woven::testers
