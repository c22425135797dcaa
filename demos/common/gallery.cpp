#include "gallery.h"

#include <fstream>

#include "core/error.h"
#include "report.h"

namespace fs = std::filesystem;

namespace rg::demos {

namespace {

std::optional<nlohmann::json> readResults(const fs::path& file) {
    std::ifstream f(file);
    if (!f) return std::nullopt;
    try {
        return nlohmann::json::parse(f);
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

}  // namespace

void writeGallery(const fs::path& outRoot, const std::vector<const Reproduction*>& papers) {
    fs::create_directories(outRoot);
    std::string body =
        "<h1>retroglass reproductions</h1>\n<p>Five papers on interactive reflections and "
        "refractions, run again on bit-exact CPU emulations of the graphics hardware they were "
        "written for. Each card links to the paper's page (figures, the paper's claims with "
        "our measurements, speed beside the paper's).</p>\n<div class=\"cards\">\n";
    for (const Reproduction* r : papers) {
        const std::string name = r->name();
        body += "<div class=\"card\" id=\"" + htmlEscape(name) + "\">\n<h2>" + htmlEscape(name) +
                "</h2>\n<p>" + htmlEscape(r->paper()) + "</p>\n<p class=\"muted\">profile <code>" +
                htmlEscape(r->profile()) + "</code></p>\n";
        std::optional<nlohmann::json> res;
        if (r->built()) res = readResults(outRoot / name / "results.json");
        if (!r->built()) {
            body += "<p class=\"muted\">not built yet</p>\n";
        } else if (!res || !fs::exists(outRoot / name / "index.html")) {
            body += "<p class=\"muted\">not run yet: <code>./retroglass reproduce " +
                    htmlEscape(name) + "</code></p>\n";
        } else {
            const auto& figs = (*res)["figures"];
            if (figs.is_array() && !figs.empty()) {
                const std::string file = figs[0].value("file", "");
                body += "<a href=\"" + htmlEscape(name + "/index.html") + "\"><img src=\"" +
                        htmlEscape(name + "/" + file) + "\" alt=\"" +
                        htmlEscape(figs[0].value("caption", "")) + "\"></a>\n";
            }
            const int held = res->value("claims_held", 0), total = res->value("claims_total", 0);
            body += std::string("<p class=\"") + (held == total ? "held" : "notheld") + "\">" +
                    std::to_string(held) + " of " + std::to_string(total) +
                    " claims hold</p>\n<p>quality <code>" +
                    htmlEscape(res->value("quality", std::string("?"))) + "</code></p>\n";
            body += "<p><a href=\"" + htmlEscape(name + "/index.html") + "\">the report</a> · <a href=\"" +
                    htmlEscape(name + "/report.md") + "\">report.md</a> · <a href=\"" +
                    htmlEscape(name + "/results.json") + "\">results.json</a></p>\n";
        }
        body += "</div>\n";
    }
    body += "</div>\n";
    if (fs::exists(outRoot / "compare" / "index.html"))
        body += "<p><a href=\"compare/index.html\">retroglass compare</a>: the techniques side "
                "by side on one scene.</p>\n";
    std::ofstream html(outRoot / "index.html");
    if (!html) throw Error((outRoot / "index.html").string() + ": cannot write");
    html << htmlPage("retroglass reproductions", body);
}

}  // namespace rg::demos
