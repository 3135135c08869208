// woven from C++, a drape stepped by its user: a built-in scene (default the paper's cube) with
// the model `woven drape` builds (testers::make_drape_model), solved by a sim::Solver one step
// at a time, its energy printed after each step. With a move step K the scene's box is
// replaced after step K by one 2 cm lower (the cloth then falls onto it).
// Built against an installed woven (examples/cpp/CMakeLists.txt: find_package(woven)).
//   drape_steps [scene, default cube] [grid, default 9] [move step, default 0: none]
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "woven/common/error.hpp"
#include "woven/geometry/primitives.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/io/scene_file.hpp"
#include "woven/sim/solver.hpp"
#include "woven/testers/drape_model.hpp"

namespace {

/// The scene's obstacles with every box lowered by `dz` (m); the others as they are.
woven::geometry::ObstacleSet lowered(const woven::geometry::ObstacleSet& obstacles, double dz)
{
    using namespace woven;
    geometry::ObstacleSet out;
    for (std::size_t i = 0; i < obstacles.size(); ++i) {
        if (const auto* box = dynamic_cast<const geometry::Box*>(&obstacles[i]))
            out.add(std::make_unique<geometry::Box>(box->centre() - Vec3(0, 0, dz), box->half_extents(), box->yaw()));
        else if (const auto* plane = dynamic_cast<const geometry::Plane*>(&obstacles[i]))
            out.add(std::make_unique<geometry::Plane>(*plane));
        else
            throw woven::InputError("drape_steps", "scene", "only planes and boxes are lowered in this example");
    }
    return out;
}

}  // namespace

int main(int argc, char** argv)
{
    using namespace woven;
    const std::string scene_name = argc > 1 ? argv[1] : "cube";
    const int grid = argc > 2 ? std::atoi(argv[2]) : 9;
    const int move_at = argc > 3 ? std::atoi(argv[3]) : 0;
    if (grid < 3 || grid > 201 || move_at < 0) {
        std::fprintf(stderr, "drape_steps: expected [scene] [grid 3..201] [move step >= 0]\n");
        return 2;
    }
    try {
        io::SceneSpec scene = io::find_scene(scene_name);
        io::SceneOverrides overrides;
        overrides.grid = grid;
        io::apply_overrides(scene, overrides, "drape_steps");
        const kes::FabricData fabric = io::find_fabric(scene.fabric);
        std::vector<std::string> warnings;
        // The command's model: the shear law de-embedded as `woven drape` does.
        const model::ClothModel cloth = testers::make_drape_model(fabric, scene.cloth.grid(), scene.model, warnings);
        for (const std::string& w : warnings) std::fprintf(stderr, "drape_steps: warning: %s\n", w.c_str());

        const sim::Problem problem{&cloth, &scene.obstacles, scene.cloth.initial_positions(), scene.pinned_indices()};
        const std::unique_ptr<sim::Solver> solver = sim::make_solver(problem, scene.solver);
        const int max_steps = sim::default_max_steps(scene.solver.kind);
        std::printf("step 0 energy %.9f J\n", solver->energy());
        while (!solver->converged() && solver->steps() < max_steps) {
            solver->step();
            std::printf("step %d t %.4f s energy %.9f J residual %.3g m g\n", solver->steps(), solver->time(), solver->energy(),
                        solver->residual());
            if (solver->steps() == move_at) {
                solver->set_obstacles(lowered(scene.obstacles, 0.02));
                std::printf("obstacles lowered by 0.02 m\n");
            }
        }
        const sim::Result result = solver->result();
        std::printf("grid %d x %d, %s after %d steps\n", cloth.grid().nu, cloth.grid().nv, result.converged ? "at rest" : "NOT at rest",
                    result.steps);
        std::printf("energy %.17g J\n", result.energy.total());
        return result.converged ? 0 : 1;
    } catch (const InputError& e) {
        std::fprintf(stderr, "drape_steps: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "drape_steps: %s\n", e.what());
        return 1;
    }
}
