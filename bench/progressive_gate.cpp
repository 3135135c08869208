// Scratch prototype for issue 32's gate (not part of the product): the progressive static drape,
// a coarse rest state carried to a finer grid and polished there by the fast solver's static
// Newton. One run per call, one JSON line on stdout (the table's row), progress on stderr.
//
//   progressive_gate direct   --grid N --seed S --save OUT.state
//       the fast solver's drape from the flat start (the direct drape), its state saved
//   progressive_gate prolong  --from COARSE.state --seed S [--save OUT.state] [--midpoint length|arc]
//       the coarse rest state (n) prolonged to 2n - 1 particles a side, pushed out of the
//       obstacles, then static Newton on the finer grid
//   progressive_gate restrict --from FINE.state --seed S [--save OUT.state] [--compare C.state]
//       every second particle of a fine rest state (n) onto (n + 1) / 2, then static Newton
// Common: --scene cube --threads 1 --h0 S (the polish's first step, s; default the largest
// step, 20 s: static from the start) --compare STATE (a state of the same grid: displacement)
// --soft-start (the polish starts in the creep's softened threads, FastSolverOptions::creep_softening)
// --contact-distance M (the barrier's d^, m: a coarse drape held off the obstacles)
// --no-polish (the start's measures only) --save-start F (the start after the push-out to F,
// before it to F.raw) --relax N (N length-restoring sweeps after the push-out).
// The scene's fabric and model; the seed only sets the direct drape's start perturbation (the
// polish starts unperturbed).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "woven/analysis/folds.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/model/cloth_model.hpp"
#include "woven/sim/contact.hpp"
#include "woven/sim/drape.hpp"
#include "woven/testers/kes_shear.hpp"

using namespace woven;

namespace {

struct State {
    int nu = 0, nv = 0;
    Positions x;
};

void save_state(const std::string& path, const State& s)
{
    std::ofstream f(path, std::ios::binary);
    f.write("WVST", 4);
    f.write(reinterpret_cast<const char*>(&s.nu), sizeof s.nu);
    f.write(reinterpret_cast<const char*>(&s.nv), sizeof s.nv);
    for (const Vec3& p : s.x) f.write(reinterpret_cast<const char*>(p.data()), 3 * sizeof(double));
    if (!f) throw std::runtime_error("cannot write " + path);
}

State load_state(const std::string& path)
{
    std::ifstream f(path, std::ios::binary);
    char magic[4];
    State s;
    f.read(magic, 4);
    f.read(reinterpret_cast<char*>(&s.nu), sizeof s.nu);
    f.read(reinterpret_cast<char*>(&s.nv), sizeof s.nv);
    if (!f || std::memcmp(magic, "WVST", 4) != 0 || s.nu < 2 || s.nv < 2) throw std::runtime_error("not a state file: " + path);
    s.x.resize(static_cast<size_t>(s.nu) * s.nv);
    for (Vec3& p : s.x) f.read(reinterpret_cast<char*>(p.data()), 3 * sizeof(double));
    if (!f) throw std::runtime_error("truncated state file: " + path);
    return s;
}

/// The scene at n particles a side, its fabric and model (as `woven drape` builds them).
struct Setup {
    io::SceneSpec scene;
    kes::FabricData fabric;
    std::optional<model::ClothModel> model;
    sim::Problem problem;

    Setup(const std::string& scene_name, int n, std::uint64_t seed, int threads)
    {
        scene = io::find_scene(scene_name);
        io::SceneOverrides ov;
        ov.grid = n;
        ov.seed = seed;
        ov.threads = threads;
        io::apply_overrides(scene, ov);
        fabric = io::find_fabric(scene.fabric);
        // as cli::resolve_shear_law (the de-embedded shear law, the drape's default)
        scene.model.shear_scale = 1.0;
        if (scene.model.shear_law == model::ShearLaw::DEEMBEDDED) scene.model.shear_scale = testers::shear_deembedding(fabric, scene.model);
        model.emplace(model::make_cloth_model(fabric, scene.cloth.grid(), scene.model));
        problem.model = &*model;
        problem.obstacles = &scene.obstacles;
        problem.initial = scene.cloth.initial_positions();
        problem.pinned = scene.pinned_indices();
    }
    const model::Grid& grid() const { return model->grid(); }
};

/// Every second particle of a (2n - 1) grid onto the n grid.
State restrict_state(const State& fine)
{
    State c;
    c.nu = (fine.nu + 1) / 2;
    c.nv = (fine.nv + 1) / 2;
    c.x.resize(static_cast<size_t>(c.nu) * c.nv);
    for (int j = 0; j < c.nv; ++j)
        for (int i = 0; i < c.nu; ++i) c.x[i + c.nu * j] = fine.x[2 * i + fine.nu * (2 * j)];
    return c;
}

/// The thread midpoint between consecutive coarse particles a and b, given their thread's
/// neighbours (the third points of the circles through three consecutive particles). ARC: the
/// midpoint of the circle's arc (the circles' sagitta vectors averaged); LENGTH: in the arc's
/// direction, as far off the chord as makes each half `half` long (on the chord when the
/// coarse segment is 2 half or longer).
enum class Midpoint { LENGTH, ARC };

Vec3 thread_midpoint(const Vec3& a, const Vec3& b, const std::vector<Vec3>& thirds, double half, Midpoint mode)
{
    const Vec3 q = 0.5 * (a + b);
    const double c = (b - a).norm();
    const Vec3 u = (b - a) / c;
    Vec3 sag = Vec3::Zero();
    int count = 0;
    for (const Vec3& t : thirds) {
        Vec3 w = q - t;
        w -= w.dot(u) * u;  // the arc not holding t lies on the chord's other side
        const double area2 = (b - a).cross(t - a).norm();  // twice the triangle's area
        ++count;
        if (w.norm() < 1e-14 || area2 < 1e-18) continue;  // collinear: no sagitta
        const double radius = c * (b - t).norm() * (a - t).norm() / (2.0 * area2);
        const double s = radius - std::sqrt(std::max(radius * radius - 0.25 * c * c, 0.0));
        sag += s * w.normalized();
    }
    if (count > 0) sag /= count;
    if (mode == Midpoint::ARC) return q + sag;
    const double h = std::sqrt(std::max(half * half - 0.25 * c * c, 0.0));
    if (h == 0.0) return q;
    Vec3 dir = sag;
    if (dir.norm() < 1e-12 * half) {  // straight and compressed: bow upward
        dir = Vec3::UnitZ() - Vec3::UnitZ().dot(u) * u;
        if (dir.norm() < 1e-12) dir = u.unitOrthogonal();
    }
    return q + h * dir.normalized();
}

/// The point whose distances to m[0..3] are closest to `len` (least squares): Levenberg-Marquardt
/// from `guess`, a step kept only where it lowers the cost.
Vec3 fit_centre(const std::array<Vec3, 4>& m, double len, Vec3 c)
{
    auto cost = [&](const Vec3& p) {
        double sum = 0;
        for (const Vec3& q : m) sum += std::pow((p - q).norm() - len, 2);
        return sum;
    };
    double f = cost(c), lambda = 1e-3;
    for (int it = 0; it < 100 && f > 1e-30 && lambda < 1e8; ++it) {
        Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
        Vec3 jtr = Vec3::Zero();
        for (const Vec3& q : m) {
            const Vec3 d = c - q;
            const double r = d.norm();
            const Vec3 g = d / std::max(r, 1e-15);
            jtj += g * g.transpose();
            jtr += g * (r - len);
        }
        const Vec3 step = -(jtj + lambda * Eigen::Matrix3d::Identity()).ldlt().solve(jtr);
        const double f_new = cost(c + step);
        if (f_new < f) {
            c += step;
            f = f_new;
            lambda = std::max(lambda / 10, 1e-9);
            if (step.norm() < 1e-14) break;
        } else {
            lambda *= 10;
        }
    }
    return c;
}

/// The coarse (n) rest state on the (2n - 1) grid of spacing sigma_fine, keeping thread lengths.
State prolong_state(const State& cs, double sigma_fine, Midpoint mode)
{
    State f;
    f.nu = 2 * cs.nu - 1;
    f.nv = 2 * cs.nv - 1;
    f.x.assign(static_cast<size_t>(f.nu) * f.nv, Vec3::Zero());
    auto C = [&](int i, int j) -> const Vec3& { return cs.x[i + cs.nu * j]; };
    auto F = [&](int a, int b) -> Vec3& { return f.x[a + f.nu * b]; };
    for (int j = 0; j < cs.nv; ++j)
        for (int i = 0; i < cs.nu; ++i) F(2 * i, 2 * j) = C(i, j);
    for (int j = 0; j < cs.nv; ++j)  // u threads
        for (int i = 0; i + 1 < cs.nu; ++i) {
            std::vector<Vec3> thirds;
            if (i > 0) thirds.push_back(C(i - 1, j));
            if (i + 2 < cs.nu) thirds.push_back(C(i + 2, j));
            F(2 * i + 1, 2 * j) = thread_midpoint(C(i, j), C(i + 1, j), thirds, sigma_fine, mode);
        }
    for (int i = 0; i < cs.nu; ++i)  // v threads
        for (int j = 0; j + 1 < cs.nv; ++j) {
            std::vector<Vec3> thirds;
            if (j > 0) thirds.push_back(C(i, j - 1));
            if (j + 2 < cs.nv) thirds.push_back(C(i, j + 2));
            F(2 * i, 2 * j + 1) = thread_midpoint(C(i, j), C(i, j + 1), thirds, sigma_fine, mode);
        }
    for (int j = 0; j + 1 < cs.nv; ++j)  // cell centres
        for (int i = 0; i + 1 < cs.nu; ++i) {
            const std::array<Vec3, 4> m{F(2 * i, 2 * j + 1), F(2 * i + 2, 2 * j + 1), F(2 * i + 1, 2 * j), F(2 * i + 1, 2 * j + 2)};
            const Vec3 mid = 0.25 * (m[0] + m[1] + m[2] + m[3]);
            const Vec3 corners = 0.25 * (C(i, j) + C(i + 1, j) + C(i, j + 1) + C(i + 1, j + 1));
            F(2 * i + 1, 2 * j + 1) = fit_centre(m, sigma_fine, 2.0 * mid - corners);
        }
    return f;
}

/// Moves every particle closer than `clearance` to an obstacle (or inside) out along the normal to
/// `clearance`; returns how many moved.
int push_out(const geometry::ObstacleSet& obstacles, Positions& x, double clearance)
{
    int moved = 0;
    for (Vec3& p : x) {
        bool was = false;
        for (int pass = 0; pass < 4; ++pass) {  // a corner of two obstacles
            const geometry::ClosestPoint cp = obstacles.closest(p);
            if (cp.distance >= clearance) break;
            p = cp.point + clearance * cp.normal;
            was = true;
        }
        moved += was;
    }
    return moved;
}

/// `sweeps` Gauss-Seidel sweeps that shorten every thread segment longer than `sigma` back to it
/// (both ends moved alike), each followed by push_out: the pushed-out particles' stretch spread
/// over their neighbours (session 8's length-restoring sweeps, with the obstacles).
void relax_lengths(const model::Grid& g, const geometry::ObstacleSet& obstacles, Positions& x, double clearance, int sweeps)
{
    auto fix = [&](int a, int b) {
        const Vec3 d = x[b] - x[a];
        const double r = d.norm();
        if (r <= g.sigma) return;
        const Vec3 corr = 0.5 * (r - g.sigma) / r * d;
        x[a] += corr;
        x[b] -= corr;
    };
    for (int s = 0; s < sweeps; ++s) {
        for (int j = 0; j < g.nv; ++j)
            for (int i = 0; i < g.nu; ++i) {
                if (i + 1 < g.nu) fix(g.index(i, j), g.index(i + 1, j));
                if (j + 1 < g.nv) fix(g.index(i, j), g.index(i, j + 1));
            }
        push_out(obstacles, x, clearance);
    }
}

nlohmann::json state_stats(const Setup& s, const Positions& x)
{
    const model::Grid& g = s.grid();
    double max_strain = -1e300, min_strain = 1e300;
    for (int j = 0; j < g.nv; ++j)
        for (int i = 0; i < g.nu; ++i) {
            const Vec3& p = x[g.index(i, j)];
            if (i + 1 < g.nu) {
                const double e = (x[g.index(i + 1, j)] - p).norm() / g.sigma - 1;
                max_strain = std::max(max_strain, e);
                min_strain = std::min(min_strain, e);
            }
            if (j + 1 < g.nv) {
                const double e = (x[g.index(i, j + 1)] - p).norm() / g.sigma - 1;
                max_strain = std::max(max_strain, e);
                min_strain = std::min(min_strain, e);
            }
        }
    const model::EnergyTerms e = s.model->evaluate(x);
    return {{"max_strain", max_strain}, {"min_strain", min_strain}, {"energy_J", e.total()}, {"stretch_J", e.stretch},
            {"min_obstacle_distance_m", sim::min_obstacle_distance(s.scene.obstacles, x)}};
}

nlohmann::json drape_measures(const Setup& s, const Positions& x)
{
    nlohmann::json j;
    const auto box = analysis::box_footprint(s.scene.obstacles);
    if (!box) return j;
    const analysis::FoldAnalysis fa = analysis::analyse_folds(analysis::grid_mesh(x, s.grid().nu, s.grid().nv), *box);
    j["lowest_z_m"] = fa.lowest_point.z();
    nlohmann::json corners = nlohmann::json::array();
    for (int c = 0; c < 4; ++c) {
        nlohmann::json per = nlohmann::json::array();
        for (const auto& sec : fa.sections) per.push_back(sec.at_corner(c).size());
        corners.push_back(per);
    }
    j["corner_billows"] = corners;
    j["hanging_m"] = {fa.hanging_m[0], fa.hanging_m[1], fa.hanging_m[2], fa.hanging_m[3]};
    return j;
}

sim::Result run(const Setup& s, const Positions& start, bool polish, double h0, bool soft_start)
{
    sim::SolverOptions o = s.scene.solver;
    if (soft_start) o.fast.creep_capped_steps = 0;  // the creep's softened threads from the first static step
    sim::Problem p = s.problem;
    p.initial = start;
    if (polish) {
        o.perturbation = 0;  // the start is the coarse rest state, not a symmetric flat sheet
        o.time_step = h0 > 0 ? h0 : o.fast.max_time_step;
    }
    return sim::drape(
        p, o,
        [](const sim::StepInfo& i) {
            std::fprintf(stderr, "  step %d  t %.4g s  E %.10f J  move %.3g m  residual %.4g m g\n", i.step, i.time, i.energy, i.max_move,
                         i.max_residual_rel);
            return true;
        });
}

}  // namespace

int main(int argc, char** argv)
{
    try {
        if (argc < 2) throw std::runtime_error("usage: progressive_gate direct|prolong|restrict [options] (see the source's head)");
        const std::string mode = argv[1];
        std::string scene = "cube", from, save, compare, save_start;
        int grid = 0, threads = 1;
        std::uint64_t seed = 1;
        double h0 = 0;
        bool no_polish = false;
        int relax = 0;
        double contact = 0;
        bool soft_start = false;
        Midpoint midpoint = Midpoint::LENGTH;
        for (int a = 2; a < argc; ++a) {
            const std::string k = argv[a];
            auto val = [&]() -> std::string {
                if (a + 1 >= argc) throw std::runtime_error(k + " needs a value");
                return argv[++a];
            };
            if (k == "--grid") grid = std::stoi(val());
            else if (k == "--seed") seed = std::stoull(val());
            else if (k == "--threads") threads = std::stoi(val());
            else if (k == "--scene") scene = val();
            else if (k == "--from") from = val();
            else if (k == "--save") save = val();
            else if (k == "--compare") compare = val();
            else if (k == "--h0") h0 = std::stod(val());
            else if (k == "--no-polish") no_polish = true;
            else if (k == "--relax") relax = std::stoi(val());
            else if (k == "--soft-start") soft_start = true;
            else if (k == "--contact-distance") contact = std::stod(val());
            else if (k == "--save-start") save_start = val();
            else if (k == "--midpoint") midpoint = val() == "arc" ? Midpoint::ARC : Midpoint::LENGTH;
            else throw std::runtime_error("unknown option " + k);
        }
        nlohmann::json row{{"mode", mode}, {"seed", seed}};
        State start;
        if (mode == "direct") {
            if (grid < 3) throw std::runtime_error("direct needs --grid");
        } else {
            const State in = load_state(from);
            row["from"] = from;
            row["from_grid"] = in.nu;
            if (mode == "prolong") grid = 2 * in.nu - 1;
            else if (mode == "restrict") grid = (in.nu + 1) / 2;
            else throw std::runtime_error("unknown mode " + mode);
            start = in;
        }
        Setup s(scene, grid, seed, threads);
        if (contact > 0) s.scene.solver.contact_distance = contact;
        row["contact_distance_m"] = s.scene.solver.contact_distance;
        row["soft_start"] = soft_start;
        row["grid"] = grid;
        Positions x0;
        if (mode == "prolong") {
            const auto t0 = std::chrono::steady_clock::now();
            x0 = prolong_state(start, s.grid().sigma, midpoint).x;
            row["midpoint"] = midpoint == Midpoint::ARC ? "arc" : "length";
            row["start_prolonged"] = state_stats(s, x0);
            if (!save_start.empty()) save_state(save_start + ".raw", State{s.grid().nu, s.grid().nv, x0});
            row["pushed_out"] = push_out(s.scene.obstacles, x0, s.scene.solver.contact_distance);
            if (relax > 0) {
                row["start_pushed"] = state_stats(s, x0);
                relax_lengths(s.grid(), s.scene.obstacles, x0, s.scene.solver.contact_distance, relax);
                row["relax_sweeps"] = relax;
            }
            row["prolong_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        } else if (mode == "restrict") {
            x0 = restrict_state(start).x;
            if (!save_start.empty()) save_state(save_start + ".raw", State{s.grid().nu, s.grid().nv, x0});
            row["pushed_out"] = push_out(s.scene.obstacles, x0, s.scene.solver.contact_distance);
        } else {
            x0 = s.problem.initial;
        }
        if (x0.size() != static_cast<size_t>(s.grid().size())) throw std::runtime_error("state and grid differ");
        row["start"] = state_stats(s, x0);
        if (!save_start.empty()) save_state(save_start, State{s.grid().nu, s.grid().nv, x0});
        if (no_polish) {
            std::cout << row.dump() << std::endl;
            return 0;
        }
        const sim::Result r = run(s, x0, mode != "direct", h0, soft_start);
        row["converged"] = r.converged;
        row["steps"] = r.steps;
        row["newton"] = r.iterations;
        row["factorizations"] = r.factorizations;
        row["cg"] = r.cg_iterations;
        row["softened_steps"] = r.softened_steps;
        row["seconds"] = r.wall_time;
        row["energy_J"] = r.energy.total();
        row["stretch_J"] = r.energy.stretch;
        row["residual_mg"] = r.equilibrium.max_residual_rel;
        row["min_obstacle_distance_m"] = sim::min_obstacle_distance(s.scene.obstacles, r.x);
        row["moved_from_start_m"] = sim::max_displacement(r.x, x0);
        row.update(drape_measures(s, r.x));
        if (!compare.empty()) {
            const State c = load_state(compare);
            if (c.x.size() != r.x.size()) throw std::runtime_error("--compare: another grid");
            double sum = 0;
            for (size_t i = 0; i < c.x.size(); ++i) sum += (c.x[i] - r.x[i]).squaredNorm();
            row["vs_compare_max_m"] = sim::max_displacement(r.x, c.x);
            row["vs_compare_rms_m"] = std::sqrt(sum / c.x.size());
        }
        if (!save.empty()) save_state(save, State{s.grid().nu, s.grid().nv, r.x});
        std::cout << row.dump() << std::endl;
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "progressive_gate: error: " << e.what() << "\n";
        return 2;
    }
}
