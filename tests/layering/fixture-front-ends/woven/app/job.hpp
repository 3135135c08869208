#pragma once
// Layering-test fixture: a job of the application floor (below the front ends).
#include "woven/io/files.hpp"
