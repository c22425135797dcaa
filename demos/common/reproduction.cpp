#include "reproduction.h"

#include <sstream>

#include "core/error.h"

namespace rg::demos {

const char* qualityName(Quality q) { return q == Quality::Paper ? "paper" : "quick"; }

Quality qualityByName(const std::string& name) {
    if (name == "quick") return Quality::Quick;
    if (name == "paper") return Quality::Paper;
    throw Error("unknown quality '" + name + "' (use quick or paper)");
}

ViewRange ViewRange::parse(const std::string& spec, int count) {
    ViewRange r;
    r.end = count;
    if (spec.empty()) return r;
    long a = 0, b = 0;
    char colon = 0;
    std::istringstream in(spec);
    if (!(in >> a >> colon >> b) || colon != ':' || !(in >> std::ws).eof() || a < 0 ||
        b > count || a >= b)
        throw Error("--views '" + spec + "': expected A:B with 0 ≤ A < B ≤ " +
                    std::to_string(count));
    r.begin = int(a);
    r.end = int(b);
    r.all = false;
    return r;
}

nlohmann::json PlannedReproduction::reproduce(const ReproduceOptions&) const {
    throw Error("reproduction '" + name_ + "' is not built yet (" + paper_ + ")");
}

}  // namespace rg::demos
