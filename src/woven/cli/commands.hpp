#pragma once
// The subcommands of `woven` (one file each) and what they share. Each run_* function returns
// the process exit code; errors are thrown (woven::InputError -> 2, anything else -> 1) and
// caught in main.cpp, which alone prints them.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "woven/app/check.hpp"
#include "woven/app/files.hpp"

namespace CLI {
class App;
}

namespace woven::cli {

// The front end calls the application floor (src/woven/app) by its names.
using namespace woven::app;

/// This program, which runs each point of a sweep or an experiment as a child process (Linux's
/// link to the running executable).
inline constexpr const char* kThisProgram = "/proc/self/exe";

/// Exit codes (README "Exit codes").
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;
inline constexpr int kExitInterrupted = 130;  ///< SIGINT (Ctrl-C); SIGTERM gives 143 (progress.hpp)

struct FabricsOptions {
    bool json = false;
};

struct ScenesOptions {
    bool json = false;
};

struct FitOptions {
    std::string fabric;
    std::optional<std::string> out;  ///< absent: out/fit-<name>; given, it must not be empty
    std::string sigma_cm = "2";      ///< parsed by run_fit (args.hpp)
    GivenFabric given_fabric;        ///< the Python module's fabric made from values
};

/// Options of `woven kes-test` (kept as text where a bad value needs the one-line error).
struct KesTestOptions {
    std::string fabric;
    std::string test = "all";
    std::string direction = "both";
    std::optional<std::string> sigma_cm;
    std::optional<std::string> shear_length_cm;
    std::optional<std::string> bending_form;
    std::optional<std::string> discretization;
    std::optional<std::string> shear_law;
    std::optional<std::string> hysteresis;  ///< friction (default) or loading-branch
    std::optional<std::string> threads;     ///< oneTBB, OpenMP and BLAS threads (0: all cores, the default)
    std::optional<std::string> out;
    bool convergence = false;
    GivenFabric given_fabric;
};

/// Options of `woven cusick`.
struct CusickCommandOptions {
    std::string fabric;
    std::string specimen_cm = "30";
    std::string disc_cm = "18";
    std::optional<std::string> spacing_cm;
    std::string seeds = "1";
    std::string seed = "1";
    std::optional<std::string> threads;
    std::optional<std::string> max_steps;
    std::optional<std::string> shear_law;
    std::optional<std::string> clamp;
    std::optional<std::string> clamp_margin;
    std::optional<std::string> clamp_gap_mm;
    std::optional<std::string> hysteresis;  ///< loading-branch (default) or friction
    std::optional<std::string> protocol;    ///< release (default) or lowered
    std::optional<std::string> shakes;      ///< quasi-static shake cycles after the protocol (default 0)
    std::optional<std::string> bias;        ///< threads or fabric (model::BiasBending)
    std::optional<std::string> solver;              ///< fast (default) or paper
    std::optional<std::string> discretization;      ///< convergent (default) or paper
    std::optional<std::string> fall_s;              ///< the fast solver's fall at its first step, s
    std::optional<std::string> thread_compression;  ///< [0, 1]
    std::optional<std::string> grid_rotation_deg;
    std::optional<std::string> start;       ///< a cusick.obj to start from
    bool search = false;                    ///< the search of rest states (testers::search_cusick)
    std::optional<std::string> modes;       ///< --search: the imposed modes, "2-12" or a list "2,4,6"
    std::optional<std::string> jobs;        ///< --search: starts run at once
    std::optional<std::string> out;
    bool no_render = false;
    GivenFabric given_fabric;
};

/// Numbers are kept as text and parsed by run_drape (args.hpp), so that a bad value gets the
/// documented one-line error.
struct DrapeOptions {
    std::string scene = "cube";
    std::optional<std::string> fabric;
    std::optional<std::string> grid;
    std::optional<std::string> solver;
    std::optional<std::string> seed;
    std::optional<std::string> threads;
    std::optional<std::string> max_steps;
    std::optional<std::string> perturb;
    std::optional<std::string> hysteresis;  ///< loading-branch or friction (overrides the scene's [model] hysteresis)
    std::optional<std::string> bias;        ///< threads or fabric (overrides the scene's [model] bias_bending)
    std::optional<std::string> start;       ///< a drape.obj of the same scene and grid to start from
    std::string out = "out";
    bool no_render = false;
    bool ply_ascii = false;
    std::string width = "1024";
    std::string height = "768";
};

/// `woven check FILE|DIR...` (cmd_check.cpp).
struct CheckOptions {
    std::vector<std::string> paths;
};

/// Adds each subcommand to `app`; the callback stores the exit code in `exit_code`.
void add_fabrics_command(CLI::App& app, int& exit_code);
void add_scenes_command(CLI::App& app, int& exit_code);
void add_fit_command(CLI::App& app, int& exit_code);
void add_kes_test_command(CLI::App& app, int& exit_code);  // cmd_kes_test.cpp
void add_drape_command(CLI::App& app, int& exit_code);
void add_render_command(CLI::App& app, int& exit_code);      // cmd_render.cpp
void add_cusick_command(CLI::App& app, int& exit_code);      // cmd_cusick.cpp
void add_garment_command(CLI::App& app, int& exit_code);     // cmd_garment.cpp
void add_experiment_command(CLI::App& app, int& exit_code);  // cmd_experiment.cpp
void add_check_command(CLI::App& app, int& exit_code);       // cmd_check.cpp
void add_sweep_command(CLI::App& app, int& exit_code);       // cmd_sweep.cpp
void add_report_command(CLI::App& app, int& exit_code);      // cmd_report.cpp

int run_fabrics(const FabricsOptions& options);
int run_scenes(const ScenesOptions& options);
int run_fit(const FitOptions& options);
int run_drape(const DrapeOptions& options);
int run_kes_test(const KesTestOptions& options);   // cmd_kes_test.cpp
int run_cusick(const CusickCommandOptions& options);  // cmd_cusick.cpp
int run_check(const CheckOptions& options);

/// Prints a line a job reports: on stdout when `out`, else on stderr (flushed).
void print_line(const std::string& line, bool out);

/// Prints "woven: warning: <w>" on stderr for each warning.
void print_warnings(const std::vector<std::string>& warnings);

}  // namespace woven::cli
