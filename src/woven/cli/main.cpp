// woven: drape of woven cloth from Kawabata (KES) measurements (Breen, House & Wozny 1994).
// Only this file catches exceptions: one line "woven: error: <what>" on stderr, then
//   0 ok, 1 runtime failure, 2 bad usage or bad input, 130 / 143 interrupted by SIGINT (Ctrl-C) /
//   SIGTERM (the state reached is written as a complete set marked interrupted).
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iostream>
#include <string_view>

#include <CLI/CLI.hpp>
#if defined(__GLIBC__)
#include <malloc.h>
#endif
#include <sys/resource.h>
#include <unistd.h>

#include "woven/cli/args.hpp"
#include "woven/cli/commands.hpp"
#include "woven/cli/progress_display.hpp"
#include "woven/common/error.hpp"

namespace woven::cli {

namespace {

/// Keeps freed blocks of up to 32 MiB in the heap instead of returning them to the kernel. Each
/// Newton iteration's factorisation allocates and frees CHOLMOD's permuted copy of the matrix
/// (84 % of the 51 x 51 cube's page faults); returned, it came back as fresh pages: the 101 x 101
/// cube made 1.51 million minor page faults instead of 26.5 thousand and spent 7.3-7.8 s of
/// system time against 2.7 s with this (bench/NOTES.md). Results do not depend on it.
void keep_freed_memory()
{
#if defined(__GLIBC__)
    constexpr int kMmapThreshold = 32 << 20;  // glibc's largest: blocks above this are mapped
    constexpr int kTrimThreshold = 64 << 20;  // free memory kept at the heap's top
    mallopt(M_MMAP_THRESHOLD, kMmapThreshold);
    mallopt(M_TRIM_THRESHOLD, kTrimThreshold);
#endif
}

/// Under an address-space or data limit (a batch scheduler's `ulimit -v`), OpenBLAS's worker
/// threads, started as the library loads (before main), may fail to map their buffers: each then
/// spins in blas_memory_alloc for ever and the exit handler waits for it (every command, even
/// --version, printed its output and never ended). woven runs its BLAS on one thread anyway
/// (sim/drape.cpp, sim/linear_solver.cpp), so under a limit the process starts again with
/// OPENBLAS_NUM_THREADS=1 (read only at load time); the exec ends the spinning threads. A value
/// the user set is replaced too (OPENBLAS_NUM_THREADS=64 under `ulimit -v 200000`: `woven
/// --version` never ended, issue 53); only 1 is kept.
void one_blas_thread_under_a_memory_limit(char** argv)
{
    if (const char* t = std::getenv("OPENBLAS_NUM_THREADS"); t != nullptr && std::string_view(t) == "1") return;
    rlimit as {}, data {};
    const bool limited = (::getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) ||
                         (::getrlimit(RLIMIT_DATA, &data) == 0 && data.rlim_cur != RLIM_INFINITY);
    if (!limited) return;
    ::setenv("OPENBLAS_NUM_THREADS", "1", 1);
    ::execv("/proc/self/exe", argv);  // returns only when it fails: go on as we are
}

}  // namespace

}  // namespace woven::cli

int main(int argc, char** argv)
{
    using namespace woven::cli;
    one_blas_thread_under_a_memory_limit(argv);
    keep_freed_memory();
    CLI::App app{"woven: drape of woven cloth from Kawabata (KES) measurements, after Breen, House & Wozny, "
                 "SIGGRAPH '94.\nExit codes: 0 ok, 1 runtime failure, 2 bad usage or input, 130 interrupted (Ctrl-C), "
                 "143 terminated (SIGTERM).",
                 "woven"};
    app.set_version_flag("--version", std::string("woven ") + WOVEN_VERSION, "Print the version and exit");
    app.require_subcommand(1, 1);
    app.fallthrough(false);

    int exit_code = kExitOk;
    add_fabrics_command(app, exit_code);
    add_scenes_command(app, exit_code);
    add_fit_command(app, exit_code);
#if __has_include("cmd_kes_test.cpp")  // subcommands still being added: registered once their file is there
    add_kes_test_command(app, exit_code);
#endif
    add_drape_command(app, exit_code);
    add_render_command(app, exit_code);
#if __has_include("cmd_cusick.cpp")
    add_cusick_command(app, exit_code);
    add_garment_command(app, exit_code);
#endif
    add_experiment_command(app, exit_code);
    add_check_command(app, exit_code);
    add_sweep_command(app, exit_code);
    add_report_command(app, exit_code);
    // The jobs' progress on stderr (the application floor prints none itself); --quiet: none.
    show_progress_on_stderr();
    for (CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
        sub->add_flag_callback("--quiet", [] { set_progress_quiet(true); }, "No progress on stderr (warnings, errors and results still)");

    try {
        // CLI11 reports a mistyped command as "A subcommand is required"; name it instead.
        std::string names;
        bool known = false;
        for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
            names += (names.empty() ? "" : ", ") + sub->get_name();
            known = known || (argc > 1 && sub->get_name() == argv[1]);
        }
        if (argc > 1 && argv[1][0] != '-' && !known) {
            std::cerr << "woven: error: command line: " << one_line(argv[1]) << ": unknown command (commands: " << names
                      << ")\n";
            return kExitUsage;
        }
        app.parse(argc, argv);
        return exit_code;
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "woven: error: command line: arguments: " << one_line(e.what()) << " (see woven --help)\n";
        return kExitUsage;
    } catch (const woven::InputError& e) {
        std::cerr << "woven: error: " << one_line(e.what()) << "\n";
        return kExitUsage;
    } catch (const std::exception& e) {
        std::cerr << "woven: error: " << one_line(e.what()) << "\n";
        return kExitFailure;
    } catch (...) {
        std::cerr << "woven: error: unknown failure\n";
        return kExitFailure;
    }
}
