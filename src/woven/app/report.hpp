#pragma once
// The report job (woven report DIR): one self-contained DIR/report.html for a sweep folder (its sweep.json and
// point folders) or for one output folder of drape, cusick, kes-test, fit, garment or an experiment: the
// table (sortable), a section per kind of folder with the plots its users read (render/plot's
// cairo SVG, each with its data and axis frame), every picture inlined, and a 3-D view of each
// drape.glb / cusick.glb / garment.glb (three.js and its GLTFLoader from Debian's libjs-three, inlined).
// Every folder is verified first (woven check's test): a broken folder is a one-line error and
// no page.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "woven/app/progress.hpp"

namespace woven::app {

struct ReportRequest {
    std::filesystem::path dir;  ///< a sweep folder or an output folder
    /// three.js and its loaders (absent: where the build found Debian's libjs-three).
    std::optional<std::filesystem::path> three_js_dir;
    /// Gets a warning when the page has no 3-D view (three.js missing). May be empty.
    std::function<void(const std::vector<std::string>&)> on_warnings;
    Monitor monitor;
};

struct ReportResult {
    std::string page;        ///< DIR/report.html
    int points = 0;          ///< rows of the table
    int scenes = 0;          ///< 3-D views inlined
    std::size_t bytes = 0;   ///< the page's size
};

/// Verifies the folder (and each done point of a sweep) and writes DIR/report.html. InputError
/// for a folder that is not one (nothing written).
ReportResult report(const ReportRequest& request);

}  // namespace woven::app
