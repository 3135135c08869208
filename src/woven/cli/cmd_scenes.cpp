// woven scenes: the built-in scenes.
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "woven/cli/commands.hpp"
#include "woven/io/scene_file.hpp"

namespace woven::cli {

int run_scenes(const ScenesOptions& options)
{
    nlohmann::json list = nlohmann::json::array();
    std::size_t width = 4;
    for (const auto& name : io::builtin_scene_names()) width = std::max(width, name.size());
    for (const auto& name : io::builtin_scene_names()) {
        const io::SceneSpec s = io::find_scene(name);
        std::string obstacles;
        for (const auto& k : s.obstacle_kinds) obstacles += (obstacles.empty() ? "" : ", ") + k;
        list.push_back({{"name", name},
                        {"description", s.description},
                        {"fabric", s.fabric},
                        {"size_m", {s.cloth.size_u, s.cloth.size_v}},
                        {"grid", {s.cloth.nu, s.cloth.nv}},
                        {"obstacles", s.obstacle_kinds}});
        if (!options.json)
            std::cout << name << std::string(width - name.size() + 2, ' ') << s.description << "\n"
                      << std::string(width + 2, ' ') << "fabric " << s.fabric << ", grid " << s.cloth.nu << " x "
                      << s.cloth.nv << ", obstacles: " << obstacles << "\n";
    }
    if (options.json) std::cout << list.dump(2) << "\n";
    return kExitOk;
}

void add_scenes_command(CLI::App& app, int& exit_code)
{
    auto options = std::make_shared<ScenesOptions>();
    CLI::App* sub = app.add_subcommand("scenes", "List the built-in scenes (usable by name in `woven drape`)");
    sub->add_flag("--json", options->json, "Machine-readable output (a JSON array)");
    sub->callback([options, &exit_code] { exit_code = run_scenes(*options); });
}

}  // namespace woven::cli
