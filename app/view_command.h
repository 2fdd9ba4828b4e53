// `gradmesh view IN -o PAGE.html [--image ORIGINAL]`: the view page (view_page.h) of a mesh
// file, kept apart from gradmesh_main.cpp like the image conversion.
#pragma once

#include <map>
#include <set>
#include <string>
#include <vector>

namespace gm {

// The valued options of `view` (besides -o/--output).
extern const std::set<std::string> kViewValuedOptions;

// Whether a report or page path names an HTML file (.html or .htm, any case).
bool isHtmlPath(const std::string& path);

// Runs the command: `positional` holds IN, `values` the valued options by name. Throws gm::Error
// for a problem with a file (nothing is written then) and std::invalid_argument for a bad
// option (the message names it).
void viewCommand(const std::vector<std::string>& positional,
                 const std::map<std::string, std::string>& values);

}  // namespace gm
