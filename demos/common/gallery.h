// out/index.html: one card per registered paper, read from each paper's results.json, with
// its first figure, how many of its claims hold, and links to its page, report.md and
// results.json. Papers not run yet or not built yet say so.
#pragma once

#include <filesystem>
#include <vector>

#include "reproduction.h"

namespace rg::demos {

void writeGallery(const std::filesystem::path& outRoot,
                  const std::vector<const Reproduction*>& papers);

}  // namespace rg::demos
