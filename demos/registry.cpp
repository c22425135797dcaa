// The one registry of the papers: `retroglass reproduce`, `view`, `bench`, `compare` and the
// gallery read this list and nothing else. Adding a paper is one line here (and its folder
// in demos/CMakeLists.txt).
#include "core/error.h"
#include "reproduction.h"
#include "reproduce_hybrid.h"
#include "reproduce_impostors.h"
#include "reproduce_lightfield.h"
#include "reproduce_pem.h"
#include "reproduce_tir.h"

namespace rg::demos {

const std::vector<const Reproduction*>& reproductions() {
    // In the order the project builds them. A paper not built yet is listed by name, paper
    // and profile; `retroglass reproduce` and the gallery say so.
    static const std::vector<const Reproduction*> all = {&pem::pemReproduction(), &hybrid::hybridReproduction(),
                                                         &lightfield::lightfieldReproduction(),
                                                         &impostors::impostorReproduction(),
                                                         &tir::tirReproduction()};
    return all;
}

const Reproduction& findReproduction(const std::string& name) {
    std::string known;
    for (const Reproduction* r : reproductions()) {
        if (r->name() == name) return *r;
        known += (known.empty() ? "" : ", ") + r->name();
    }
    throw Error("unknown reproduction '" + name + "' (known: " + known + ")");
}

}  // namespace rg::demos
