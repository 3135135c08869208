// woven sweep PLAN.toml: runs the points of a plan (batch/sweep_plan.hpp, docs/SWEEP-FORMAT.md),
// each as a child process of this binary running the plan's command (drape, cusick, kes-test)
// into a private work folder; a point that finishes and verifies is renamed into place as
// <sweep>/<point name>/, so a point's folder is there complete (its manifest, every file's
// SHA-256, point.json) or not at all. Resume is the default: a point whose folder verifies with
// the plan's command line is not run again. --jobs J runs J points at once; the points are
// split between the ranks of a launcher (Open MPI, PMI, a Slurm array) or --shard I/N, every
// rank writing into the shared folder and merging (sweep.csv, sweep.json) at its end under a
// lock on the folder; --merge merges alone, idempotently.
#include <cstdlib>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "woven/batch/sweep.hpp"
#include "woven/cli/args.hpp"
#include "woven/cli/commands.hpp"
#include "woven/batch/sweep_plan.hpp"

namespace woven::cli {

using namespace woven::batch;

namespace {

struct SweepOptions {
    std::string plan;
    std::optional<std::string> out;
    std::string jobs = "1";
    std::optional<std::string> shard;
    bool merge = false;
    bool list = false;
};

/// `s` as one shell word: unchanged when it holds only [A-Za-z0-9_./=:,+@%-], else in single quotes.
std::string shell_quote(const std::string& s)
{
    const bool plain = !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || std::strchr("_./=:,+@%-", c) != nullptr;
    });
    if (plain) return s;
    std::string q = "'";
    for (const char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

int run_sweep(const SweepOptions& o)
{
    std::vector<std::string> warnings;
    const batch::SweepPlan plan = batch::load_sweep_plan(o.plan, &warnings);
    print_warnings(warnings);
    const std::string out = o.out ? parse_path(*o.out, "--out") : join_path("out", "sweep-" + plan.name);
    SweepRunOptions run;
    run.executable = kThisProgram;
    run.jobs = static_cast<int>(parse_integer(o.jobs, "--jobs", kJobsRange[0], kJobsRange[1]));
    run.shard = shard_from(o.shard, [](const char* name) { return std::getenv(name); });
    run.on_line = print_line;
    if (o.list || o.merge) {
        validate_sweep_overrides(plan);
        if (o.list) {
            // One point at a time (a million points are not held at once); every word shell-quoted
            // where it needs it, so that a pasted line runs the same command.
            std::string line;
            for (std::size_t index = 0; index < plan.size(); ++index) {
                const batch::SweepPoint p = plan.point(index);
                line = std::to_string(p.index) + " " + p.name + (in_shard(p.index, run.shard) ? "" : " (other shard)") + ":";
                for (const auto& a : p.args) line += " " + shell_quote(a);
                for (const auto& v : p.scene_overrides) line += " " + shell_quote("scene." + v.key + "=" + v.text);
                for (const auto& v : p.fabric_overrides) line += " " + shell_quote("fabric." + v.key + "=" + v.text);
                line += "\n";
                std::cout << line;
            }
            return kExitOk;
        }
        make_output_dir(out);
        const MergeCounts c = merge_sweep(plan, out);
        std::cout << "merged " << plan.size() << " points into " << join_path(out, "sweep.csv") << " and " << join_path(out, "sweep.json")
                  << ": " << c.done << " done, " << c.failed << " failed, " << c.missing << " missing\n";
        return kExitOk;
    }
    const SweepRunResult r = run_sweep_points(plan, out, run);
    if (r.signal != 0) return 128 + r.signal;
    return r.failed > 0 ? kExitFailure : kExitOk;
}

}  // namespace

void add_sweep_command(CLI::App& app, int& exit_code)
{
    auto o = std::make_shared<SweepOptions>();
    CLI::App* sub = app.add_subcommand("sweep", "Run every point of a sweep plan (docs/SWEEP-FORMAT.md), resuming, on one machine or many");
    sub->footer("Each point runs the plan's command (drape, cusick or kes-test) as a child process and appears as <out>/<point>/ only "
                "once complete and verified (its manifest's SHA-256s and point.json). A point whose folder verifies is not run again; "
                "a failed or killed one is. The points are split by rank: --shard I/N, else Open MPI's OMPI_COMM_WORLD_RANK/SIZE, "
                "PMI_RANK/SIZE or Slurm's SLURM_ARRAY_TASK_ID/COUNT; every rank merges sweep.csv and sweep.json at its end, and "
                "--merge merges alone (idempotent). Exit 0 when every point of this shard is done, 1 when one failed, 130/143 when "
                "interrupted.");
    sub->add_option("PLAN", o->plan, "The plan, a .toml file")->required();
    sub->add_option("--out", o->out, "The sweep folder (default out/sweep-<plan name>)");
    sub->add_option("--jobs", o->jobs, "Points run at once on this machine (the cores are divided between them)")
        ->capture_default_str()
        ->type_name(int_type(kJobsRange));
    sub->add_option("--shard", o->shard, "Run shard I of N (0 <= I < N): the points whose index modulo N is I")->type_name("I/N");
    sub->add_flag("--merge", o->merge, "Only merge the finished points into sweep.csv and sweep.json");
    sub->add_flag("--list", o->list, "List the points and their command lines, run nothing");
    sub->callback([o, &exit_code] { exit_code = run_sweep(*o); });
}

}  // namespace woven::cli
