// The reader of a scene's [certification] table (the keys: sim/drop/certification.hpp and
// docs/certification.md).
#pragma once

#include <string>

#include <toml++/toml.h>

#include "sim/drop/certification.hpp"

namespace lg {

// Parses and validates a [certification] table for 'scene' (its bodies, struts and tyres must be built);
// 'basis' (if not empty) replaces the table's basis. Throws InputError naming file, line and key.
Certification parseCertification(const toml::table& t, const std::string& file, const Scene& scene,
                                 const std::string& basis = "");

}  // namespace lg
