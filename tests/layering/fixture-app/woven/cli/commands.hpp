#pragma once
// Layering-test fixture: the command line builds on the application floor.
#include "woven/app/job.hpp"
