// The built-in data: src/woven/io/CMakeLists.txt lists the files compiled into the binary by name;
// every fabric, scene and mesh of the repository must be among them, and nothing else.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <string>
#include <utility>

#include "woven/io/embedded_data.hpp"

namespace {

TEST(EmbeddedData, HoldsEveryFabricSceneAndMeshOfTheRepository)
{
    namespace fs = std::filesystem;
    std::set<std::string> on_disk;
    for (const auto& [folder, extension] : {std::pair{"fabrics", ".toml"}, {"scenes", ".toml"}, {"assets", ".obj"}})
        for (const auto& entry : fs::directory_iterator(fs::path(WOVEN_SOURCE_DIR) / folder))
            if (entry.is_regular_file() && entry.path().extension() == extension)
                on_disk.insert(std::string(folder) + "/" + entry.path().filename().string());
    std::set<std::string> embedded;
    for (const auto& file : woven::io::data::embedded_files()) embedded.insert(std::string(file.path));
    EXPECT_GE(on_disk.size(), 17u);  // 11 fabrics, 5 scenes, 1 mesh when this test was written
    EXPECT_EQ(embedded, on_disk) << "add the new file to the list in src/woven/io/CMakeLists.txt";
}

}  // namespace
