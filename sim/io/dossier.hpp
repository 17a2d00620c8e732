// The sections of the compliance dossier that say where every number comes from (compliance.md and
// compliance.json, sim/io/compliance.hpp): the configuration under test (every value of the scene
// with its unit, and what derives from them), the model and the solver with the accuracy each case
// achieved, the rules' paragraphs behind each case, the derivation of each case's W, L, V, h and W_e,
// the assumptions and exclusions, and the footnotes of the tables.
#pragma once

#include <string>

#include "sim/drop/certification.hpp"

namespace lg {

// The rules' paragraphs behind a matrix case for its basis ("14 CFR 25.473(a)(2)(i), 25.723(a)"), and
// the older numbering where one exists; for a check, "the scene's own case (a check)".
std::string ruleParagraphs(const Certification& c, const CertCase& cc);

// The equivalent free-drop height h = V^2 / (2 g) [m] and the effective mass of the rigs' reduced-mass
// method, W_e = W [h + (1 - L) d] / (h + d), d the vertical travel after touchdown (the case's h_max) [kg].
double dropHeight(double V, double g);
double effectiveMass(double W, double L, double h, double d);

// The markdown sections: configuration, method and accuracy, the cases' rules and derivations,
// assumptions and exclusions, footnotes. 'scene' is the scene the cases ran on.
std::string configurationMarkdown(const Scene& scene);
std::string methodMarkdown(const Scene& scene, const Compliance& c);
std::string derivationMarkdown(const Scene& scene, const Compliance& c);
std::string assumptionsMarkdown(const Scene& scene, const Compliance& c);
std::string footnotesMarkdown(const Compliance& c);

// The same facts for compliance.json: "configuration", "method", "assumptions" members (no trailing comma).
std::string dossierJson(const Scene& scene, const Compliance& c);

}  // namespace lg
