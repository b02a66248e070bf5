// Files shipped with beadtwin and embedded in the binary at build time: the default scenario and the
// machine and material library (scenarios/data/*.yaml, scenarios/data/machines/*.yaml,
// scenarios/data/materials/*.yaml).
#pragma once

#include <map>
#include <string>

namespace beadtwin::scenarios {

// Keyed by path relative to scenarios/ ("default.yaml", "machines/lsam-ph15.yaml").
const std::map<std::string, std::string>& shipped_files();

}  // namespace beadtwin::scenarios
