// woven check FILE|DIR...: each argument checked (app/check.hpp). One line per problem on stderr
// ("woven: error: ..."), the readers' warnings as the commands print them, one "<path>: ok (...)"
// line per sound argument on stdout; exit 0 when all are sound, 2 otherwise.
#include <iostream>
#include <memory>

#include <CLI/CLI.hpp>

#include "woven/app/check.hpp"
#include "woven/cli/commands.hpp"

namespace woven::cli {

int run_check(const CheckOptions& options)
{
    bool sound = true;
    for (const auto& arg : options.paths) {
        const CheckResult r = check_path(arg);
        print_warnings(r.warnings);
        for (const auto& p : r.problems) std::cerr << "woven: error: " << one_line(p) << "\n";
        if (r.problems.empty()) std::cout << arg << ": ok (" << r.what << ")\n";
        sound = sound && r.problems.empty();
    }
    return sound ? kExitOk : kExitUsage;
}

void add_check_command(CLI::App& app, int& exit_code)
{
    auto o = std::make_shared<CheckOptions>();
    CLI::App* sub = app.add_subcommand("check", "Validate fabric and scene files, meshes and output folders without simulating");
    sub->footer("A .toml file is read as a fabric or a scene (a scene's fabric and mesh files too) by the readers the other "
                "commands use, with their messages and warnings; an .obj file as an obstacle mesh; a folder as a finished "
                "output set: its manifest (report.json, cusick.json or kes-report.json) parses, every file it lists is there "
                "with its size and SHA-256, its numbers are finite and its OBJ and GLB meshes read; a sweep folder (sweep.json): "
                "every point it lists as done verifies so; an experiment's folder: each of its sets (cube_results.json, "
                "corner_map.json, figure1.json) verifies. One line per problem on stderr; exit 0 when all is "
                "well, 2 otherwise.");
    sub->add_option("FILE|DIR", o->paths, "Files and output folders to check")->required();
    sub->callback([o, &exit_code] { exit_code = run_check(*o); });
}

}  // namespace woven::cli
