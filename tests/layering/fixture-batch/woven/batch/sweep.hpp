#pragma once
// Layering-test fixture: the batch floor runs the application floor's jobs.
#include "woven/app/job.hpp"
