#pragma once
// Layering-test fixture: a job of the application floor including the batch floor above it
// (must be reported).
#include "woven/batch/sweep.hpp"
