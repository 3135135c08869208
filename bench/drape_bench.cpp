// Macro benchmark: the paper's cube drape (cotton, from the flat start to rest) with woven's
// solvers and the Bullet peer on the same scene, run one after another in one process so that
// their ratios are measured under the same load. Writes
//   <out>/runs.json   every run: command, wall and CPU seconds, peak RSS, load average, and the
//                     drape's steps, Newton iterations, factorisations, CG iterations, residual,
//                     energy (woven) or simulated seconds reached (Bullet)
//   <out>/table.md    the grid x solver x threads table with the ratios and the targets
//   <out>/time_vs_particles.png   log-log picture of time against particle count
// Usage: drape_bench --woven BUILD/woven [--bullet BUILD/bench/peers/bullet_drape] --out DIR
//        [--grids 51,101,201] [--paper-grids 21,51] [--repeat 3] [--bullet-max-wall 300]
//        [--max-wall 1800] [--reference-energy 0.4760152] [--skip-threads2]
//        drape_bench --from-runs DIR/runs.json [--from-runs MORE.json ...] --out DIR2   tabulates
//        earlier, possibly killed runs, several files together
#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <nlohmann/json.hpp>
#include <sys/resource.h>
#include <sys/select.h>
#include <sys/wait.h>
#include <unistd.h>

#include "woven/render/image.hpp"
#include "woven/render/plot.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct Options {
    std::string woven, bullet, out = "bench-out";
    std::string blender, blender_script;  ///< the blender binary and bench/peers/blender_drape.py
    int blender_max_grid = 51;            ///< Blender only up to this grid (it needs minutes beyond)
    std::vector<int> grids{51, 101, 201}, paper_grids{21, 51};
    int repeat = 3;                // runs of a case whose first run is under repeat_below_s
    double repeat_below_s = 60;    // s
    double bullet_max_wall = 300;  // s of Bullet stepping (its --maxwall)
    double max_wall = 1800;        // s: a run is killed after this
    double reference_energy = 0;   // J: the 51 x 51 final energy before the performance work
    bool threads2 = true;
    std::vector<std::string> from_runs;  // runs.json files to tabulate together instead of running
};

struct Outcome {
    double wall = 0, cpu = 0;  // s of the whole process
    long max_rss_kib = 0;
    int status = -1;
    bool killed = false;
    std::string stdout_text;
};

double load_average()
{
    std::ifstream f("/proc/loadavg");
    double l = 0;
    f >> l;
    return l;
}

/// Runs argv, capturing stdout; kills it after max_wall seconds. Peak RSS and CPU time from wait4.
Outcome run_process(const std::vector<std::string>& argv, double max_wall)
{
    Outcome o;
    int pipe_fd[2];
    if (pipe(pipe_fd) != 0) throw std::runtime_error("pipe failed");
    const auto t0 = std::chrono::steady_clock::now();
    const pid_t pid = fork();
    if (pid < 0) throw std::runtime_error("fork failed");
    if (pid == 0) {
        dup2(pipe_fd[1], STDOUT_FILENO);
        close(pipe_fd[0]);
        close(pipe_fd[1]);
        const int devnull = ::open("/dev/null", O_WRONLY);
        if (devnull >= 0) dup2(devnull, STDERR_FILENO);
        std::vector<char*> args;
        for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
        args.push_back(nullptr);
        execv(args[0], args.data());
        _exit(127);
    }
    close(pipe_fd[1]);
    char buf[4096];
    // Read until EOF, polling the deadline.
    for (;;) {
        fd_set set;
        FD_ZERO(&set);
        FD_SET(pipe_fd[0], &set);
        timeval tv{1, 0};
        const int ready = select(pipe_fd[0] + 1, &set, nullptr, nullptr, &tv);
        if (ready > 0) {
            const ssize_t got = read(pipe_fd[0], buf, sizeof buf);
            if (got <= 0) break;
            o.stdout_text.append(buf, static_cast<size_t>(got));
        }
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (elapsed > max_wall && !o.killed) {
            kill(pid, SIGKILL);
            o.killed = true;
        }
    }
    close(pipe_fd[0]);
    rusage usage{};
    int status = 0;
    wait4(pid, &status, 0, &usage);
    o.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    o.cpu = usage.ru_utime.tv_sec + 1e-6 * usage.ru_utime.tv_usec + usage.ru_stime.tv_sec + 1e-6 * usage.ru_stime.tv_usec;
    o.max_rss_kib = usage.ru_maxrss;
    o.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return o;
}

std::string join(const std::vector<std::string>& argv)
{
    std::string s;
    for (const std::string& a : argv) s += (s.empty() ? "" : " ") + a;
    return s;
}

/// One woven drape of the cube; the report's numbers plus the process's.
/// Runs argv, recording in r the load before, the command, wall and CPU time, peak RSS and how
/// it ended.
Outcome measured_run(const Options& opt, const std::vector<std::string>& argv, json& r)
{
    r["load_average_before"] = load_average();
    const Outcome o = run_process(argv, opt.max_wall);
    r["command"] = join(argv);
    r["process_wall_s"] = o.wall;
    r["cpu_s"] = o.cpu;
    r["max_rss_mib"] = o.max_rss_kib / 1024.0;
    r["exit"] = o.status;
    r["killed"] = o.killed;
    return o;
}

json run_woven(const Options& opt, const std::string& solver, int grid, int threads, int rep)
{
    const std::string dir =
        opt.out + "/runs/" + solver + "-" + std::to_string(grid) + "-t" + std::to_string(threads) + "-r" + std::to_string(rep);
    const std::vector<std::string> argv{
        opt.woven,     "drape", "cube", "--grid", std::to_string(grid), "--solver", solver, "--threads", std::to_string(threads),
        "--no-render", "--out", dir};
    json r{{"tool", "woven"}, {"solver", solver}, {"grid", grid}, {"particles", grid * grid}, {"threads", threads}, {"repeat", rep}};
    const Outcome o = measured_run(opt, argv, r);
    std::ifstream in(dir + "/report.json");
    if (in) {
        const json report = json::parse(in, nullptr, false);
        if (!report.is_discarded()) {
            for (const char* k : {"converged", "steps", "iterations", "factorizations", "cg_iterations", "simulated_time_s", "wall_time_s"})
                if (report.contains(k)) r[k] = report[k];
            r["energy_J"] = report["energy"]["total_J"];
            r["max_residual_rel"] = report["equilibrium"]["max_residual_rel"];
            r["max_penetration_m"] = report["contact"]["max_penetration_m"];
            r["strain_max"] = report["strain"]["max"];
        }
    }
    // The solver's own wall time excludes start-up (scene, fabric fit, output), as Bullet's does.
    r["time_s"] = r.contains("wall_time_s") ? r["wall_time_s"].get<double>() : o.wall;
    std::cerr << "drape_bench: woven " << solver << " " << grid << " t" << threads << " r" << rep << ": " << r["time_s"].get<double>()
              << " s\n";
    return r;
}

/// A peer's run (Bullet, Blender: the scene of ../shared/peers, their own settle rule and JSON):
/// its time is its own stepping time (`wall_seconds`), start-up excluded, as woven's is.
json run_peer(const Options& opt, const std::string& tool, const std::vector<std::string>& argv, const std::string& json_path, int grid,
              int rep, int threads)
{
    json r{{"tool", tool}, {"solver", tool}, {"grid", grid}, {"particles", grid * grid}, {"threads", threads}, {"repeat", rep}};
    const Outcome o = measured_run(opt, argv, r);
    std::ifstream in(json_path);
    if (in) {
        const json b = json::parse(in, nullptr, false);
        if (!b.is_discarded())
            for (const char* k : {"sim_seconds", "wall_seconds", "settled", "capped_by_wall", "last_frame_max_disp_m"})
                if (b.contains(k)) r[k] = b[k];
    }
    r["time_s"] = r.contains("wall_seconds") ? r["wall_seconds"].get<double>() : o.wall;
    std::cerr << "drape_bench: " << tool << " " << grid << " r" << rep << ": " << r["time_s"].get<double>() << " s\n";
    return r;
}

json run_bullet(const Options& opt, int grid, int rep)
{
    const std::string json_path = opt.out + "/runs/bullet-" + std::to_string(grid) + "-r" + std::to_string(rep) + ".json";
    return run_peer(opt, "bullet",
                    {opt.bullet, "--n", std::to_string(grid), "--maxwall", std::to_string(opt.bullet_max_wall), "--snap-every", "0", "--json",
                     json_path},
                    json_path, grid, rep, 1);
}

/// Blender 3.4's cloth (the Cotton preset, bench/peers/blender_drape.py) on all cores.
json run_blender(const Options& opt, int grid, int rep)
{
    const std::string json_path = opt.out + "/runs/blender-" + std::to_string(grid) + "-r" + std::to_string(rep) + ".json";
    const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    return run_peer(opt, "blender",
                    {opt.blender, "-b", "--factory-startup", "--python", opt.blender_script, "--", "--n", std::to_string(grid), "--maxwall",
                     std::to_string(opt.bullet_max_wall), "--snap-every", "0", "--json", json_path},
                    json_path, grid, rep, cores);
}

double median(std::vector<double> v)
{
    if (v.empty()) return NAN;
    std::sort(v.begin(), v.end());
    const size_t m = v.size() / 2;
    return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

std::string fmt(double v, const char* f = "%.3g")
{
    if (!std::isfinite(v)) return "-";
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

/// A comma-separated list of grid sides, each an integer >= 3 ("" is an empty list); exits 2
/// naming the option otherwise.
std::vector<int> parse_list(const std::string& s, const std::string& option)
{
    std::vector<int> v;
    std::stringstream ss(s);
    for (std::string item; std::getline(ss, item, ',');) {
        if (item.empty()) continue;
        std::size_t used = 0;
        int n = 0;
        try {
            n = std::stoi(item, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used != item.size() || n < 3) {
            std::cerr << "drape_bench: " << option << ": expected grid sides >= 3 separated by commas, got '" << item << "'\n";
            std::exit(2);
        }
        v.push_back(n);
    }
    return v;
}

struct Case {
    std::string tool, solver;
    int grid, threads;
    bool operator<(const Case& o) const { return std::tie(tool, solver, grid, threads) < std::tie(o.tool, o.solver, o.grid, o.threads); }
};

}  // namespace

int main(int argc, char** argv)
{
    Options opt;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) {
                std::cerr << "drape_bench: " << a << " needs a value\n";
                std::exit(2);
            }
            return argv[++i];
        };
        if (a == "--woven")
            opt.woven = value();
        else if (a == "--bullet")
            opt.bullet = value();
        else if (a == "--out")
            opt.out = value();
        else if (a == "--grids")
            opt.grids = parse_list(value(), a);
        else if (a == "--paper-grids")
            opt.paper_grids = parse_list(value(), a);
        else if (a == "--repeat")
            opt.repeat = std::stoi(value());
        else if (a == "--blender")
            opt.blender = value();
        else if (a == "--blender-script")
            opt.blender_script = value();
        else if (a == "--blender-max-grid")
            opt.blender_max_grid = std::stoi(value());
        else if (a == "--bullet-max-wall")
            opt.bullet_max_wall = std::stod(value());
        else if (a == "--max-wall")
            opt.max_wall = std::stod(value());
        else if (a == "--reference-energy")
            opt.reference_energy = std::stod(value());
        else if (a == "--from-runs")
            opt.from_runs.push_back(value());
        else if (a == "--skip-threads2")
            opt.threads2 = false;
        else if (a == "--help" || a == "-h") {
            std::cout << "usage: drape_bench --woven WOVEN [--bullet BULLET] --out DIR [--grids 51,101,201] [--paper-grids 21,51]\n"
                         "       [--repeat 3] [--bullet-max-wall 300] [--max-wall 1800] [--reference-energy J] [--skip-threads2]\n"
                         "       [--blender BLENDER --blender-script bench/peers/blender_drape.py] [--blender-max-grid 51]\n"
                         "       drape_bench --from-runs RUNS.json [--from-runs MORE.json ...] --out DIR [--reference-energy J]   (tabulate earlier runs)\n";
            return 0;
        } else {
            std::cerr << "drape_bench: unknown option " << a << "\n";
            return 2;
        }
    }
    if (opt.from_runs.empty() && opt.grids.empty()) {
        std::cerr << "drape_bench: --grids: at least one grid side is expected\n";
        return 2;
    }
    if (opt.from_runs.empty() && (opt.woven.empty() || access(opt.woven.c_str(), X_OK) != 0)) {
        std::cerr << "drape_bench: --woven: an executable woven binary is expected\n";
        return 2;
    }
    const bool with_bullet = !opt.bullet.empty() && access(opt.bullet.c_str(), X_OK) == 0;
    const bool with_blender = !opt.blender.empty() && access(opt.blender.c_str(), X_OK) == 0 && access(opt.blender_script.c_str(), R_OK) == 0;
    fs::create_directories(opt.out + "/runs");

    json runs = json::array();
    std::map<Case, std::vector<json>> by_case;
    auto add = [&](const json& r) {
        runs.push_back(r);
        by_case[{r["tool"], r["solver"], r["grid"], r["threads"]}].push_back(r);
        std::ofstream(opt.out + "/runs.json") << runs.dump(1) << "\n";  // kept current: a killed bench keeps its runs
    };
    if (!opt.from_runs.empty()) {
        // Tabulate earlier (possibly interrupted) runs instead of running: several files are
        // tabulated together (a long run made on its own beside a make bench, say).
        // All are read before any is written: <out>/runs.json may be one of them.
        std::vector<json> earlier;
        for (const std::string& file : opt.from_runs) {
            std::ifstream in(file);
            earlier.push_back(json::parse(in, nullptr, false));
            if (earlier.back().is_discarded() || !earlier.back().is_array()) {
                std::cerr << "drape_bench: " << file << ": a JSON array of runs is expected\n";
                return 2;
            }
        }
        for (const json& file_runs : earlier)
            for (const json& r : file_runs) add(r);
        opt.grids.clear();
        opt.paper_grids.clear();
        for (const auto& [c, rs] : by_case) {
            auto& list = c.solver == "paper" ? opt.paper_grids : opt.grids;
            if (c.tool == "woven" && std::find(list.begin(), list.end(), c.grid) == list.end()) list.push_back(c.grid);
        }
        std::sort(opt.grids.begin(), opt.grids.end());
        std::sort(opt.paper_grids.begin(), opt.paper_grids.end());
    }
    for (int grid : opt.from_runs.empty() ? opt.grids : std::vector<int>{}) {
        // woven one thread and Bullet alternate, so each pair runs under the same load.
        const bool bullet_here = with_bullet && grid <= 101;
        for (int rep = 1; rep <= opt.repeat; ++rep) {
            const json w = run_woven(opt, "fast", grid, 1, rep);
            add(w);
            if (bullet_here) add(run_bullet(opt, grid, rep));
            if (opt.threads2) add(run_woven(opt, "fast", grid, 2, rep));
            if (rep == 1 && grid == opt.grids.front()) add(run_woven(opt, "fast", grid, 0, rep));
            if (w["time_s"].get<double>() > opt.repeat_below_s) break;
        }
        if (with_bullet && !bullet_here) add(run_bullet(opt, grid, 1));  // capped by --bullet-max-wall
        if (with_blender && grid <= opt.blender_max_grid) add(run_blender(opt, grid, 1));
    }
    for (int grid : opt.from_runs.empty() ? opt.paper_grids : std::vector<int>{}) {
        add(run_woven(opt, "paper", grid, 1, 1));
        if (!by_case.count({"woven", "fast", grid, 1})) add(run_woven(opt, "fast", grid, 1, 1));  // the ratio's other half
    }

    // ---- table ----
    auto med = [&](const Case& c, const char* key) {
        std::vector<double> v;
        for (const json& r : by_case[c])
            if (r.contains(key) && r[key].is_number()) v.push_back(r[key].get<double>());
        return median(v);
    };
    std::ostringstream md;
    md << "| tool | solver | grid | particles | threads | runs | time (s, median) | CPU (s) | peak RSS (MiB) | steps | Newton its | "
          "factorisations | CG its | converged | energy (J) | residual (m g) | load avg |\n";
    md << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& [c, rs] : by_case) {
        const json& r0 = rs.front();
        auto s = [&](const char* k, const char* f = "%.3g") { return fmt(med(c, k), f); };
        std::string conv = "-";
        if (r0.contains("converged")) conv = r0["converged"].get<bool>() ? "yes" : "no";
        if (r0.contains("settled"))
            conv = r0["settled"].get<bool>() ? "settled" : "no (" + fmt(med(c, "sim_seconds"), "%.1f") + " s simulated)";
        if (r0.value("killed", false)) conv = "killed at " + fmt(opt.max_wall, "%.0f") + " s";
        md << "| " << c.tool << " | " << c.solver << " | " << c.grid << " x " << c.grid << " | " << c.grid * c.grid << " | "
           << (c.threads == 0 ? std::string("default") : std::to_string(c.threads)) << " | " << rs.size() << " | " << s("time_s", "%.2f")
           << " | " << s("cpu_s", "%.2f") << " | " << s("max_rss_mib", "%.0f") << " | " << s("steps", "%.0f") << " | "
           << s("iterations", "%.0f") << " | " << s("factorizations", "%.0f") << " | " << s("cg_iterations", "%.0f") << " | " << conv
           << " | " << s("energy_J", "%.7f") << " | " << s("max_residual_rel", "%.2g") << " | " << s("load_average_before", "%.1f")
           << " |\n";
    }

    // ---- targets ----
    auto t = [&](const std::string& tool, const std::string& solver, int g, int th) { return med({tool, solver, g, th}, "time_s"); };
    md << "\n| target | measured | met |\n|---|---|---|\n";
    auto row = [&](const std::string& what, const std::string& measured, bool ok, bool known) {
        md << "| " << what << " | " << measured << " | " << (known ? (ok ? "yes" : "**no**") : "not measured") << " |\n";
    };
    // woven / Bullet at 51 from the alternating pairs (same load).
    {
        std::vector<double> ratios;
        const auto& w = by_case[{"woven", "fast", 51, 1}];
        const auto& b = by_case[{"bullet", "bullet", 51, 1}];
        for (size_t k = 0; k < std::min(w.size(), b.size()); ++k)
            ratios.push_back(w[k]["time_s"].get<double>() / b[k]["time_s"].get<double>());
        const double r = median(ratios);
        row("51 x 51: woven at least 20 x faster than Bullet (woven/Bullet <= 0.05), one thread each, same run",
            "ratio " + fmt(r, "%.3f") + " (Bullet/woven " + fmt(1 / r, "%.1f") + " x; pairs: " + std::to_string(ratios.size()) + ")",
            r <= 0.05, std::isfinite(r));
    }
    {
        // Blender runs once per grid, on all cores (its cloth solver is threaded): a reference, not a target.
        for (const auto& [c, rs] : by_case) {
            if (c.tool != "blender") continue;
            const double tb = med(c, "time_s"), tw = t("woven", "fast", c.grid, 1);
            row(std::to_string(c.grid) + " x " + std::to_string(c.grid) + ": woven (one thread) against Blender (" + std::to_string(c.threads) +
                    " threads), for reference",
                "woven/Blender " + fmt(tw / tb, "%.3f") + " (Blender " + fmt(tb, "%.1f") + " s)", tw / tb <= 0.05, std::isfinite(tw / tb));
        }
    }
    const double t51 = t("woven", "fast", 51, 1), t101 = t("woven", "fast", 101, 1), t201 = t("woven", "fast", 201, 1);
    row("101 x 101 <= 5 s, one thread", fmt(t101, "%.2f") + " s", t101 <= 5, std::isfinite(t101));
    row("201 x 201 <= 30 s, one thread", fmt(t201, "%.2f") + " s", t201 <= 30, std::isfinite(t201));
    {
        const double p = std::log(t201 / t51) / std::log(201.0 * 201 / (51.0 * 51));
        const double p101 = std::log(t101 / t51) / std::log(101.0 * 101 / (51.0 * 51));
        row("cost growth <= n^1.3 from 51 to 201 (n particles)", "n^" + fmt(p, "%.2f") + " (51 to 101: n^" + fmt(p101, "%.2f") + ")",
            p <= 1.3, std::isfinite(p));
    }
    {
        const double s201 = t201 / t("woven", "fast", 201, 2);
        row("201 x 201: two threads >= 1.6 x faster than one", fmt(s201, "%.3f") + " x", s201 >= 1.6, std::isfinite(s201));
        std::string m;
        bool ok = true, known = false;
        for (int g : opt.grids) {
            const double s = t("woven", "fast", g, 1) / t("woven", "fast", g, 2);
            if (!std::isfinite(s)) continue;
            known = true;
            ok = ok && s >= 1.0;
            m += (m.empty() ? "" : ", ") + std::to_string(g) + ": " + fmt(s, "%.2f") + " x";
        }
        row("two threads never slower than one (speed-up t1/t2 >= 1 at every grid)", m, ok, known);
        if (!opt.grids.empty()) {
            const int g = opt.grids.front();
            const double sd = t("woven", "fast", g, 1) / t("woven", "fast", g, 0);
            row("default threads never slower than one (" + std::to_string(g) + " x " + std::to_string(g) + ")", fmt(sd, "%.2f") + " x",
                sd >= 1.0, std::isfinite(sd));
        }
    }
    for (int threads : {1, 2}) {  // two: the default on a 2-core machine
        constexpr double kMegabytesPerMebibyte = 1.048576;
        const double rss = med({"woven", "fast", 201, threads}, "max_rss_mib"), megabytes = rss * kMegabytesPerMebibyte;
        row("peak memory at 201 x 201 < 400 MB (" + std::string(threads == 1 ? "one thread" : "two threads") + ")",
            fmt(megabytes, "%.0f") + " MB (" + fmt(rss, "%.0f") + " MiB)", megabytes < 400, std::isfinite(rss));
    }
    for (int g : opt.paper_grids) {
        const double r = t("woven", "paper", g, 1) / t("woven", "fast", g, 1);
        row("paper solver / fast solver at " + std::to_string(g) + " x " + std::to_string(g) + " (a measured ratio)",
            fmt(r, "%.1f") + " (paper " + fmt(t("woven", "paper", g, 1), "%.1f") + " s, fast " + fmt(t("woven", "fast", g, 1), "%.2f")
                + " s)",
            true, std::isfinite(r));
    }
    if (opt.reference_energy > 0) {
        const double e = med({"woven", "fast", 51, 1}, "energy_J");
        const double rel = (e - opt.reference_energy) / opt.reference_energy;
        row("51 x 51 final energy within 1e-4 relative of " + fmt(opt.reference_energy, "%.7f") + " J, or lower",
            fmt(e, "%.7f") + " J (" + fmt(rel, "%+.2e") + ")", rel <= 1e-4, std::isfinite(e));
    }
    std::ofstream(opt.out + "/table.md") << md.str();

    // ---- picture: log10 time against log10 particles ----
    woven::render::Plot plot;
    plot.title = "Cube drape, cotton: time against particle count (log-log)";
    plot.x_label = "log10 particles";
    plot.y_label = "log10 time (s)";
    std::map<std::string, woven::render::Series> series;
    const woven::Vec3 colours[] = {{0.12, 0.47, 0.71}, {1.0, 0.5, 0.05}, {0.17, 0.63, 0.17}, {0.84, 0.15, 0.16}, {0.58, 0.40, 0.74}};
    for (const auto& [c, rs] : by_case) {
        if (c.threads == 0) continue;
        std::string label = c.tool == "bullet"    ? "Bullet 3.24, 20 simulated s or 300 s cap"
            : c.tool == "blender"                 ? "Blender 3.4 (Cotton preset, all cores), 20 simulated s or cap"
                                                  : "woven " + c.solver + ", " + std::to_string(c.threads) + " thread" + (c.threads > 1 ? "s" : "");
        auto& s = series[label];
        s.label = label;
        s.style = woven::render::Series::Style::LINE_AND_POINTS;
        s.x.push_back(std::log10(static_cast<double>(c.grid) * c.grid));
        s.y.push_back(std::log10(med(c, "time_s")));
    }
    int k = 0;
    for (auto& [label, s] : series) {
        s.color = colours[k++ % 5];
        plot.series.push_back(s);
    }
    woven::render::write_png(woven::render::plot(plot, 900, 600), opt.out + "/time_vs_particles.png");
    std::ofstream(opt.out + "/table.md") << md.str();
    std::cout << md.str();
    return 0;
}
