#pragma once
// Fabric files (TOML): KES summary values or first-stage curves of one fabric, parsed into
// kes::FabricData. The format is documented in docs/FABRIC-FORMAT.md; the built-in fabrics are
// the fabrics/*.toml files compiled into the binary (woven::io::data::embedded_files()).
#include <string>
#include <string_view>
#include <vector>

#include "woven/kes/fabric.hpp"

namespace woven::io {

/// Parses a fabric TOML text; `source` names it in errors (the file path, or "built-in fabric
/// 'cotton'"). Summary values (B, 2HB; G, 2HG, 2HG5) are turned into curves with
/// kes::synthesize_bending_curve / kes::synthesize_shear_curve; point lists are taken as the
/// curve and leave the summary empty. Ends with kes::validate. Every error is an InputError
/// "<source>: <field>: <what is expected>"; TOML syntax errors read "<source>:<line>:<column>:
/// <description>". Unknown keys and kes::validate's range warnings are appended to `warnings`
/// (when given), each prefixed with the source.
kes::FabricData parse_fabric(std::string_view toml_text, const std::string& source,
                             std::vector<std::string>* warnings = nullptr);

/// Reads a fabric file (throws InputError "<path>: cannot read file" when missing).
kes::FabricData load_fabric_file(const std::string& path, std::vector<std::string>* warnings = nullptr);

/// Names of the built-in fabrics (the embedded fabrics/*.toml, without directory and extension), sorted.
std::vector<std::string> builtin_fabric_names();

/// A built-in fabric by name, or a file when `name_or_path` ends in .toml or contains '/'.
/// Unknown name -> InputError listing the built-in names.
kes::FabricData find_fabric(const std::string& name_or_path, std::vector<std::string>* warnings = nullptr);

}  // namespace woven::io
