// The subcommands of `wavevcm`; each returns the process exit code.
#pragma once

#include "../render/RenderOptions.h"
#include "../report/Report.h"

#include <string>

namespace wv {



int runRender(const RenderOptions& options);
int runDevices();
int runCompare(const std::string& test, const std::string& reference, double maxRelMse);

// scenes/cornell-box.gltf next to the installed binary or in the source tree.
std::string defaultScenePath();

} // namespace wv
