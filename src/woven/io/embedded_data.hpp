#pragma once
// The data files compiled into the binary (fabrics/, scenes/, assets/), see cmake/embed.cmake.
#include <span>

#include "woven/common/embedded.hpp"

namespace woven::io::data {
std::span<const EmbeddedFile> embedded_files();
}  // namespace woven::io::data
