#include "woven/app/drape_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "woven/common/units.hpp"
#include "woven/testers/specimen.hpp"

namespace woven::app {

KesValues kes_values(const kes::FabricData& f)
{
    KesValues v;
    v.W = f.areal_density_mg_cm2;
    v.B_warp = testers::input_B(f, testers::Direction::WARP);
    v.B_weft = testers::input_B(f, testers::Direction::WEFT);
    v.G = testers::input_G(f);
    return v;
}

namespace {

nlohmann::json vec(const Vec3& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

/// JSON has no inf/NaN: nlohmann writes them as null; keep that explicit.
nlohmann::json num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json energy_json(const model::EnergyTerms& e)
{
    return {{"repulsion_J", num(e.repulsion)},       {"stretch_J", num(e.stretch)},
            {"bending_warp_J", num(e.bending_warp)}, {"bending_weft_J", num(e.bending_weft)},
            {"trellis_J", num(e.trellis)},           {"gravity_J", num(e.gravity)},
            {"twist_J", num(e.twist)},               {"total_J", num(e.total())}};
}

}  // namespace

nlohmann::json model_json(const model::ClothModel& model, const model::ModelOptions& o)
{
    const bool convergent = model.discretization() == model::Discretization::CONVERGENT;
    return {{"discretization", model::to_string(model.discretization())},
            {"bending_form", o.bending_form == model::BendingForm::WORK ? "work" : "secant"},
            {"shear_law", model::to_string(o.shear_law)},
            {"shear_scale", model.shear_scale()},
            {"hysteresis", model::to_string(model.hysteresis())},
            {"bias_bending", model::to_string(model.twist_rigidity() > 0 ? model::BiasBending::FABRIC : model::BiasBending::THREADS)},
            {"twist_rigidity_N_m", model.twist_rigidity()},
            {"gram_force", units::to_string(o.gram_force)},
            {"dyn_per_gram_force", units::dyn_per_gram_force(o.gram_force)},
            {"tensile_stiffness_N_m", convergent ? model.spacing().tensile : 0.0},
            {"thread_compression", convergent ? model.spacing().compression_ratio : 0.0},
            {"C0_J", model.spacing().C0},
            {"gravity_m_s2", model.gravity()},
            {"sigma_m", model.sigma()}};
}

nlohmann::json solver_result_json(const sim::Result& r, bool fast_counters)
{
    nlohmann::json j = {{"converged", r.converged}, {"steps", r.steps}, {"iterations", r.iterations}, {"wall_time_s", num(r.wall_time)}};
    if (fast_counters) {
        j["factorizations"] = r.factorizations;
        j["cg_iterations"] = r.cg_iterations;
        j["softened_steps"] = r.softened_steps;
    }
    return j;
}

nlohmann::json drape_report(const DrapeReportInput& in)
{
    const auto& model = *in.model;
    const auto& r = *in.result;
    const auto& grid = model.grid();
    const analysis::StateMeasures m = analysis::measure_state(r.x, grid, *in.obstacles, in.solver->contact_distance, model.stencils().active);
    const KesValues kv = kes_values(*in.fabric_data);

    nlohmann::json j;
    j["version"] = WOVEN_VERSION;
    j["scene"] = in.scene;
    j["scene_source"] = in.scene_source;
    j["fabric"] = in.fabric;
    j["grid"] = {grid.nu, grid.nv};
    j["particles"] = grid.size();
    j["sigma_m"] = grid.sigma;
    j["solver"] = sim::to_string(in.solver->kind);
    j["seed"] = in.solver->seed;
    j["threads"] = in.solver->threads;
    j["friction"] = in.solver->friction;
    j["max_steps"] = in.solver->max_steps;
    j.update(solver_result_json(r, in.solver->kind == sim::SolverKind::FAST));
    j["interrupted"] = in.interrupted || r.interrupted;
    if (in.solver->kind == sim::SolverKind::FAST) {
        j["creep_softening"] = in.solver->fast.creep_softening;
        j["fall_duration_s"] = in.solver->fast.fall_duration;
    }
    j["simulated_time_s"] = num(r.simulated_time);
    j["energy"] = energy_json(r.energy);
    j["energy_initial_J"] = num(in.energy_initial);
    j["equilibrium"] = {{"max_move_m", num(r.equilibrium.max_move)},
                        {"max_residual_rel", num(r.equilibrium.max_residual_rel)},
                        {"residual_tolerance", in.solver->residual_tolerance}};
    j["contact"] = {{"max_penetration_m", num(m.max_penetration)},
                    {"particles", m.contact_particles},
                    {"contact_distance_m", in.solver->contact_distance}};
    j["strain"] = {{"max", num(m.strain_max)},
                   {"min", num(m.strain_min)},
                   {"mean", num(m.strain_mean)},
                   {"max_abs", num(m.strain_max_abs)}};
    j["bbox"] = {{"min_m", vec(m.bbox_min)}, {"max_m", vec(m.bbox_max)}};
    j["particle_mass_kg"] = model.particle_mass();
    j["gravity_m_s2"] = model.gravity();
    j["C0_J"] = model.spacing().C0;
    j["shear_scale"] = model.shear_scale();
    if (in.model_options) j["model"] = model_json(model, *in.model_options);
    j["kes"] = {{"W_mg_cm2", kv.W},
                {"B_warp_gf_cm2_cm", kv.B_warp},
                {"B_weft_gf_cm2_cm", kv.B_weft},
                {"G_gf_cm_deg", kv.G}};
    j["outputs"] = in.outputs;
    j["folds"] = in.folds ? folds_json(*in.folds) : nlohmann::json(nullptr);
    return j;
}

nlohmann::json folds_json(const analysis::FoldAnalysis& fa, const analysis::FoldOptions& options)
{
    nlohmann::json f;
    f["heights_m"] = nlohmann::json::array();
    f["depths_m"] = nlohmann::json::array();
    f["sections"] = nlohmann::json::array();
    for (const auto& s : fa.sections) {
        f["heights_m"].push_back(num(s.height_m));
        f["depths_m"].push_back(num(s.depth_m));
        f["sections"].push_back({{"height_m", num(s.height_m)}, {"found", s.found}, {"closed", s.closed},
                                 {"length_m", num(s.length_m)}});
    }
    f["prominence_m"] = options.prominence_m;
    f["corner_cone_deg"] = analysis::kCornerConeDeg;
    f["fold_standout_fraction"] = analysis::kFoldStandoutFraction;
    f["corners"] = nlohmann::json::array();
    for (int c = 0; c < 4; ++c) {
        nlohmann::json corner{{"corner", c}, {"billows", nlohmann::json::array()}, {"angles_deg", nlohmann::json::array()},
                              {"standout_m", nlohmann::json::array()}, {"structure", nlohmann::json::array()},
                              {"asymmetry_deg", nlohmann::json::array()}, {"folds", nlohmann::json::array()},
                              {"fold_angles_deg", nlohmann::json::array()}, {"side_wave_angles_deg", nlohmann::json::array()}};
        for (const auto& s : fa.sections) {
            const std::vector<analysis::Billow> at = s.at_corner(c);
            corner["structure"].push_back(analysis::to_string(analysis::corner_structure(at)));
            corner["asymmetry_deg"].push_back(num(analysis::corner_asymmetry_deg(at)));
            const analysis::CornerBillows split = analysis::split_corner_billows(at);
            nlohmann::json fold_angles = nlohmann::json::array(), wave_angles = nlohmann::json::array();
            for (const auto& b : split.folds) fold_angles.push_back(num(b.angle_deg));
            for (const auto& b : split.side_waves) wave_angles.push_back(num(b.angle_deg));
            corner["folds"].push_back(split.folds.size());
            corner["fold_angles_deg"].push_back(fold_angles);
            corner["side_wave_angles_deg"].push_back(wave_angles);
            nlohmann::json angles = nlohmann::json::array(), standout = nlohmann::json::array();
            for (const auto& b : s.at_corner(c)) {
                angles.push_back(num(b.angle_deg));
                standout.push_back(num(b.standout_m));
            }
            corner["billows"].push_back(angles.size());
            corner["angles_deg"].push_back(angles);
            corner["standout_m"].push_back(standout);
        }
        f["corners"].push_back(corner);
    }
    f["lowest_point_m"] = vec(fa.lowest_point);
    f["hanging_m"] = {num(fa.hanging_m[0]), num(fa.hanging_m[1]), num(fa.hanging_m[2]), num(fa.hanging_m[3])};
    f["projected_area_m2"] = num(fa.projected_area_m2);
    return f;
}

std::string folds_summary(const nlohmann::json& f)
{
    static const char* names[4] = {"+x +y", "-x +y", "-x -y", "+x -y"};
    std::ostringstream s;
    char buf[96];
    for (int c = 0; c < 4; ++c) {
        const auto& corner = f["corners"][c];
        s << "corner " << c << " (" << names[c] << "):";
        for (std::size_t h = 0; h < f["heights_m"].size(); ++h) {
            const auto& angles = corner["angles_deg"][h];
            const auto& standout = corner["standout_m"][h];
            std::snprintf(buf, sizeof buf, "%s %zu billow%s at z %.2f m", h ? ";" : "", angles.size(),
                          angles.size() == 1 ? "" : "s", f["heights_m"][h].is_number() ? f["heights_m"][h].get<double>() : 0.0);
            s << buf;
            for (std::size_t k = 0; k < angles.size(); ++k) {
                std::snprintf(buf, sizeof buf, "%s%+.0f deg %.3f m", k ? ", " : " (", angles[k].is_number() ? angles[k].get<double>() : 0.0,
                              standout[k].is_number() ? standout[k].get<double>() : 0.0);
                s << buf;
            }
            if (!angles.empty()) s << ")";
            if (corner["structure"][h].is_string()) s << ": " << corner["structure"][h].get<std::string>();
        }
        s << "\n";
    }
    return s.str();
}

std::string drape_summary(const nlohmann::json& r)
{
    auto g = [](const nlohmann::json& v) -> std::string {
        if (!v.is_number()) return "n/a";
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.4g", v.get<double>());
        return buf;
    };
    std::ostringstream s;
    s << "scene " << r["scene"].get<std::string>() << ", fabric " << r["fabric"].get<std::string>() << ", grid "
      << r["grid"][0] << " x " << r["grid"][1] << ", solver " << r["solver"].get<std::string>() << "\n";
    s << "converged:   " << (r["converged"].get<bool>() ? "yes" : "no")
      << (r["interrupted"].get<bool>() ? " (interrupted)" : "") << "\n";
    s << "steps:       " << r["steps"] << " (" << r["iterations"] << " iterations), simulated "
      << g(r["simulated_time_s"]) << " s, wall " << g(r["wall_time_s"]) << " s\n";
    s << "energy:      " << g(r["energy"]["total_J"]) << " J (initial " << g(r["energy_initial_J"]) << " J)\n";
    s << "equilibrium: max move " << g(r["equilibrium"]["max_move_m"]) << " m, max residual "
      << g(r["equilibrium"]["max_residual_rel"]) << " m g\n";
    s << "contact:     max penetration " << g(r["contact"]["max_penetration_m"]) << " m, "
      << r["contact"]["particles"] << " particles in contact\n";
    s << "strain:      max " << g(r["strain"]["max"]) << ", min " << g(r["strain"]["min"]) << ", mean "
      << g(r["strain"]["mean"]) << "\n";
    if (r.contains("folds") && r["folds"].is_object()) s << folds_summary(r["folds"]);
    return s.str();
}

}  // namespace woven::app
