// The demos `retroglass view` knows. A new paper adds its line here; nothing else in the
// viewer changes.
#include "demo.h"
#include "pem_demo.h"

namespace rg::viewer {

const std::vector<DemoEntry>& demoRegistry() {
    static const std::vector<DemoEntry> demos = {
        {"pem", "Hakura, Snyder & Lengyel, Parameterized Environment Maps, I3D 2001",
         [](const DemoOptions& o) -> std::unique_ptr<Demo> { return std::make_unique<pem::PemDemo>(o); }},
    };
    return demos;
}

}  // namespace rg::viewer
