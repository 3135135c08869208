// woven from C++: the built-in cotton draped over a sphere on a floor, its energy printed.
// Built against an installed woven (examples/cpp/CMakeLists.txt: find_package(woven)).
//   drape_sphere [grid points per side, default 11]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "woven/common/error.hpp"
#include "woven/geometry/primitives.hpp"
#include "woven/io/fabric_file.hpp"
#include "woven/model/cloth_model.hpp"
#include "woven/sim/contact.hpp"
#include "woven/sim/drape.hpp"
#include "woven/testers/drape_model.hpp"

int main(int argc, char** argv)
{
    using namespace woven;
    const int n = argc > 1 ? std::atoi(argv[1]) : 11;
    if (n < 3 || n > 201) {
        std::fprintf(stderr, "drape_sphere: grid points per side: expected an integer in 3..201\n");
        return 2;
    }
    try {
        // A 0.5 m square of cotton, n x n particles, 5 mm above a 0.3 m sphere on the floor.
        const kes::FabricData cotton = io::find_fabric("cotton");
        const model::Grid grid{n, n, 0.5 / (n - 1)};
        // The command's model: the shear law de-embedded as `woven drape` does it.
        std::vector<std::string> warnings;
        const model::ClothModel cloth = testers::make_drape_model(cotton, grid, model::ModelOptions{}, warnings);

        geometry::ObstacleSet obstacles;
        obstacles.add(std::make_unique<geometry::Plane>(Vec3::Zero(), Vec3::UnitZ()));
        obstacles.add(std::make_unique<geometry::Sphere>(Vec3(0, 0, 0.15), 0.15));

        sim::Problem problem;
        problem.model = &cloth;
        problem.obstacles = &obstacles;
        problem.initial = model::flat_grid(grid, Vec3(0, 0, 0.305));
        problem.pinned = {grid.index(n / 2, n / 2)};  // held over the pole (no friction holds it)

        sim::SolverOptions options;  // the fast solver, seed 1
        const sim::Result result = sim::drape(problem, options);

        std::printf("grid %d x %d, %s after %d steps\n", n, n, result.converged ? "at rest" : "NOT at rest", result.steps);
        std::printf("energy %.6f J (start %.6f J)\n", result.energy.total(), cloth.energy(problem.initial));
        std::printf("lowest particle %.4f m, deepest penetration %.2e m\n", [&] {
            double z = result.x[0].z();
            for (const Vec3& p : result.x) z = std::min(z, p.z());
            return z;
        }(), std::max(0.0, -sim::min_obstacle_distance(obstacles, result.x)));
        return result.converged ? 0 : 1;
    } catch (const InputError& e) {
        std::fprintf(stderr, "drape_sphere: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "drape_sphere: %s\n", e.what());
        return 1;
    }
}
