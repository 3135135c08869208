// Layering-test fixture: the Python module on the command line (must be reported).
#include "woven/app/job.hpp"
#include "woven/cli/commands.hpp"
