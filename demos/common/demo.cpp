// The demo interface's parameter helpers (demo.h).
#include "demo.h"

#include "core/error.h"

namespace rg::viewer {

Param& findParam(std::vector<Param>& params, const std::string& name) {
    for (Param& p : params)
        if (p.name == name) return p;
    throw Error("unknown parameter '" + name + "'");
}

double paramValue(const std::vector<Param>& params, const std::string& name) {
    for (const Param& p : params)
        if (p.name == name) return p.value;
    throw Error("unknown parameter '" + name + "'");
}

}  // namespace rg::viewer
