// woven report DIR: the folder as a report request (app/report.hpp); the page's size printed.
#include <iostream>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "woven/app/report.hpp"
#include "woven/cli/commands.hpp"

namespace woven::cli {

namespace {

struct ReportOptions {
    std::string dir;
};

int run_report(const ReportOptions& o)
{
    ReportRequest request;
    request.dir = o.dir;
    request.on_warnings = print_warnings;
    const ReportResult r = report(request);
    std::cout << "wrote " << r.page << " (" << r.points << (r.points == 1 ? " point, " : " points, ") << r.scenes
              << (r.scenes == 1 ? " scene, " : " scenes, ") << (r.bytes + 512) / 1024 << " KiB)\n";
    return kExitOk;
}

}  // namespace

void add_report_command(CLI::App& app, int& exit_code)
{
    auto o = std::make_shared<ReportOptions>();
    CLI::App* sub = app.add_subcommand("report", "Write one self-contained report.html for a sweep or an output folder");
    sub->footer("DIR is a sweep folder (woven sweep) or an output folder of drape, cusick, kes-test, fit, garment or experiment. The page holds "
                "the table (click a header to sort), a section per kind of folder with its plots (SVG, each with its data), the pictures "
                "and a 3-D view of each drape.glb, cusick.glb or garment.glb coloured by any per-vertex field (three.js from libjs-three), all inlined: "
                "it opens from a file without a network. Every folder is verified first (as woven check does); a broken one is an error "
                "and no page is written.");
    sub->add_option("DIR", o->dir, "The folder")->required();
    sub->callback([o, &exit_code] { exit_code = run_report(*o); });
}

}  // namespace woven::cli
