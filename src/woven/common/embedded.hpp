#pragma once
// A data file compiled into the binary (cmake/embed.cmake).
#include <span>
#include <string_view>

namespace woven {

struct EmbeddedFile {
    std::string_view path;  ///< path relative to the repository root, e.g. "fabrics/cotton.toml"
    std::string_view data;  ///< file contents
};

}  // namespace woven
