#include "woven/render/image.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>

#include <stb/stb_image_write.h>

#include "woven/common/error.hpp"

namespace woven::render {

namespace {

void append_bytes(void* context, void* data, int size)
{
    auto* out = static_cast<std::vector<std::uint8_t>*>(context);
    const auto* bytes = static_cast<const std::uint8_t*>(data);
    out->insert(out->end(), bytes, bytes + size);
}

[[noreturn]] void fail(const std::string& path, const std::string& reason)
{
    throw RuntimeError("cannot write " + path + ": " + reason);
}

}  // namespace

std::string encode_png(const Image& image, const std::string& path)
{
    if (image.width <= 0 || image.height <= 0) fail(path, "empty image");
    if (image.rgb.size() != static_cast<std::size_t>(image.width) * image.height * 3)
        fail(path, "pixel buffer size does not match width x height x 3");
    std::vector<std::uint8_t> encoded;
    const int ok = stbi_write_png_to_func(append_bytes, &encoded, image.width, image.height, 3,
                                          image.rgb.data(), image.width * 3);
    if (ok == 0 || encoded.empty()) fail(path, "PNG encoding failed");
    return std::string(encoded.begin(), encoded.end());
}

void write_png(const Image& image, const std::string& path)
{
    const std::string encoded = encode_png(image, path);

    const std::string tmp = path + ".tmp";
    std::FILE* file = std::fopen(tmp.c_str(), "wb");
    if (file == nullptr) fail(path, std::strerror(errno));
    const std::size_t written = std::fwrite(encoded.data(), 1, encoded.size(), file);
    const int write_errno = errno;
    const bool flushed = std::fflush(file) == 0;
    const int flush_errno = errno;
    const bool closed = std::fclose(file) == 0;
    const int close_errno = errno;
    if (written != encoded.size() || !flushed || !closed) {
        std::remove(tmp.c_str());
        const int e = written != encoded.size() ? write_errno : (!flushed ? flush_errno : close_errno);
        fail(path, e != 0 ? std::strerror(e) : "short write");
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const int e = errno;
        std::remove(tmp.c_str());
        fail(path, std::strerror(e));
    }
}

}  // namespace woven::render
