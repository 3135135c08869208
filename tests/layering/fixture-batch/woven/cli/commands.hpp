#pragma once
// Layering-test fixture: the command line calls both floors.
#include "woven/app/job.hpp"
#include "woven/batch/sweep.hpp"
