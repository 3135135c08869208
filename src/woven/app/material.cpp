#include "woven/app/material.hpp"

#include <iomanip>
#include <sstream>

namespace woven::app {

std::string shear_law_text(const model::ModelOptions& options)
{
    std::ostringstream s;
    s << "shear law " << to_string(options.shear_law) << " (input curve x " << std::fixed << std::setprecision(4) << options.shear_scale << ")";
    return s.str();
}

}  // namespace woven::app
