#pragma once
// 8-bit RGB images and atomic PNG output.
#include <cstdint>
#include <string>
#include <vector>

namespace woven::render {

/// An 8-bit sRGB image: `rgb` holds width * height * 3 bytes, row-major, top row first.
struct Image {
    int width = 0;                   ///< pixels
    int height = 0;                  ///< pixels
    std::vector<std::uint8_t> rgb;   ///< R, G, B per pixel, row-major, top row first
};

/// Writes `image` as a PNG atomically: to "<path>.tmp", then renamed onto `path`.
/// Throws woven::RuntimeError("cannot write <path>: <reason>") on failure (including an
/// empty image or one whose buffer size does not match), leaving no partial file behind.
void write_png(const Image& image, const std::string& path);
/// The PNG file's bytes (what write_png writes), for an output set that writes them itself
/// (io::OutputSet::add, whose errors name the output, not a temporary). RuntimeError naming
/// `name` for an empty or inconsistent image.
std::string encode_png(const Image& image, const std::string& name);

}  // namespace woven::render
