// Layering-test fixture: the Python module binds the application floor.
#include "woven/app/job.hpp"
