// write_png: round trip through stb_image, atomic write, errors.
#include <cstdio>
#include <filesystem>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>
#include <stb/stb_image.h>

#include "woven/common/error.hpp"
#include "woven/render/image.hpp"

namespace fs = std::filesystem;
using woven::render::Image;
using woven::render::write_png;

namespace {

fs::path scratch_dir(const std::string& name)
{
    const fs::path dir = fs::temp_directory_path() / ("woven_test_render_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

Image gradient(int w, int h)
{
    Image img;
    img.width = w;
    img.height = h;
    img.rgb.resize(static_cast<std::size_t>(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            std::uint8_t* p = &img.rgb[(static_cast<std::size_t>(y) * w + x) * 3];
            p[0] = static_cast<std::uint8_t>(x * 7);
            p[1] = static_cast<std::uint8_t>(y * 13);
            p[2] = static_cast<std::uint8_t>((x + y) * 3);
        }
    return img;
}

}  // namespace

TEST(WritePng, RoundTripsExactlyAndLeavesNoTmp)
{
    const fs::path dir = scratch_dir("roundtrip");
    const std::string path = (dir / "g.png").string();
    const Image img = gradient(37, 23);
    write_png(img, path);
    EXPECT_FALSE(fs::exists(path + ".tmp"));
    int w = 0, h = 0, c = 0;
    unsigned char* data = stbi_load(path.c_str(), &w, &h, &c, 3);
    ASSERT_NE(data, nullptr);
    EXPECT_EQ(w, 37);
    EXPECT_EQ(h, 23);
    EXPECT_TRUE(std::equal(img.rgb.begin(), img.rgb.end(), data));  // lossless, top row first
    stbi_image_free(data);

    // Overwriting an existing file works too.
    write_png(gradient(5, 4), path);
    ASSERT_NE(stbi_info(path.c_str(), &w, &h, &c), 0);
    EXPECT_EQ(w, 5);
    EXPECT_EQ(h, 4);
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 1);
    fs::remove_all(dir);
}

TEST(WritePng, MissingDirectoryThrowsAndCreatesNothing)
{
    const fs::path dir = scratch_dir("missing");
    const fs::path missing = dir / "no" / "such";
    const std::string path = (missing / "x.png").string();
    try {
        write_png(gradient(4, 4), path);
        FAIL() << "expected RuntimeError";
    }
    catch (const woven::RuntimeError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("cannot write " + path + ": ", 0), 0u) << e.what();
    }
    EXPECT_FALSE(fs::exists(dir / "no"));
    EXPECT_TRUE(fs::is_empty(dir));
    fs::remove_all(dir);
}

TEST(WritePng, InconsistentImageThrowsAndCreatesNothing)
{
    const fs::path dir = scratch_dir("bad");
    Image img = gradient(4, 4);
    img.rgb.pop_back();
    EXPECT_THROW(write_png(img, (dir / "a.png").string()), woven::RuntimeError);
    EXPECT_THROW(write_png(Image{}, (dir / "b.png").string()), woven::RuntimeError);
    EXPECT_TRUE(fs::is_empty(dir));
    fs::remove_all(dir);
}
