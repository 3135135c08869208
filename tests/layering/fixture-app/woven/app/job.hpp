#pragma once
// Layering-test fixture: the application floor including the command line (must be reported).
#include "woven/io/files.hpp"
#include "woven/cli/commands.hpp"
