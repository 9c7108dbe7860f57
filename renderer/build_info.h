// What this kiln is: its version, the git commit it was built from and the versions of the
// libraries it uses (compiled against, and OCIO's and TBB's as loaded). For --version and the EXR.
#pragma once

#include <string>

namespace kiln {

std::string gitCommit();  // "1a2b3c4d5e6f" (+ "-dirty"), or "unknown" outside a git checkout
// "embree 3.13.5, OpenImageIO 2.4.7, ..." on one line.
std::string libraryVersions();
// kiln --version: "kiln VERSION (commit ...)" then one line per library.
std::string versionText();

}  // namespace kiln
