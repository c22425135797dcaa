#include "reproductions.h"

#include "reproduce_pem.h"

namespace rg::demos {

const std::vector<Reproduction>& reproductions() {
    // Listed in the order the project builds them (DEVELOPERS.md). A reproduction that
    // does not exist yet has no `run`, and `retroglass reproduce` says so.
    static const std::vector<Reproduction> kAll = {
        {"pem", "Hakura, Snyder & Lengyel, \"Parameterized Environment Maps\", I3D 2001",
         "geforce256", &pem::reproducePem},
        {"hybrid",
         "Hakura & Snyder, \"Realistic Reflections and Refractions on Graphics Hardware With "
         "Hybrid Rendering and Layered Environment Maps\", EGWR 2001",
         "geforce256", {}},
        {"lightfield",
         "Heidrich, Lensch, Cohen & Seidel, \"Light Field Techniques for Reflections and "
         "Refractions\", EGWR 1999",
         "sgi-octane-mxe", {}},
        {"impostors",
         "Dancsik & Minarik, \"Real-time multi-bounce many-object ray tracing with "
         "distance-normal impostors\"",
         "geforce8800", {}},
        {"tir", "Davis & Wyman, \"Interactive Refractions with Total Internal Reflection\", 2007",
         "geforce8800", {}},
    };
    return kAll;
}

}  // namespace rg::demos
