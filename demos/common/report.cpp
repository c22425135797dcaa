#include "report.h"

#include <cmark-gfm-core-extensions.h>
#include <cmark-gfm.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <map>
#include <mutex>

#include "core/error.h"

namespace fs = std::filesystem;

namespace rg::demos {

namespace {

std::string cell(const std::string& s) {
    // A Markdown table cell: pipes escaped, line breaks folded.
    std::string out;
    for (char c : s) {
        if (c == '|') out += "\\|";
        else if (c == '\n') out += ' ';
        else out += c;
    }
    return out;
}

// The measured values of a claim as one line: "a = 1.23, b = 4.56".
std::string measuredText(const nlohmann::json& m) {
    std::string s;
    for (const auto& [k, v] : m.items()) {
        if (!s.empty()) s += ", ";
        s += k + " = ";
        if (v.is_number_float()) s += num(v.get<double>(), 3);
        else if (v.is_string()) s += v.get<std::string>();
        else s += v.dump();
    }
    return s;
}

void writeFile(const fs::path& path, const std::string& text) {
    // Written beside and renamed, so a reader never sees half a file.
    fs::path tmp = path;
    tmp += ".part";
    {
        std::ofstream f(tmp, std::ios::binary);
        if (!f) throw Error(path.string() + ": cannot write");
        f << text;
        if (!f.flush()) throw Error(path.string() + ": write failed (disk full?)");
    }
    fs::rename(tmp, path);
}

}  // namespace

std::string num(double v, int decimals) {
    if (std::isnan(v)) return "—";
    if (std::isinf(v)) return v > 0 ? "∞" : "−∞";
    char b[64];
    std::snprintf(b, sizeof b, "%.*f", decimals, v);
    return b;
}

Claim claimAtLeast(std::string id, std::string section, std::string statement,
                   const std::string& nameA, double a, const std::string& nameB, double b,
                   double margin, const std::string& unit) {
    Claim c;
    c.id = std::move(id);
    c.section = std::move(section);
    c.statement = std::move(statement);
    c.test = nameA + " − " + nameB + " ≥ " + num(margin, 2) + (unit.empty() ? "" : " " + unit);
    c.measured[nameA] = a;
    c.measured[nameB] = b;
    c.measured["difference"] = a - b;
    c.holds = std::isfinite(a - b) ? a - b >= margin : (a > b);
    return c;
}

Claim claimWithin(std::string id, std::string section, std::string statement,
                  const std::string& nameA, double a, const std::string& nameB, double b,
                  double tolerance, const std::string& unit) {
    Claim c;
    c.id = std::move(id);
    c.section = std::move(section);
    c.statement = std::move(statement);
    c.test = "|" + nameA + " − " + nameB + "| ≤ " + num(tolerance, 2) +
             (unit.empty() ? "" : " " + unit);
    c.measured[nameA] = a;
    c.measured[nameB] = b;
    c.measured["difference"] = a - b;
    c.holds = std::abs(a - b) <= tolerance;
    return c;
}

nlohmann::json claimToJson(const Claim& c) {
    return {{"id", c.id},           {"section", c.section}, {"statement", c.statement},
            {"test", c.test},       {"measured", c.measured}, {"holds", c.holds}};
}

std::string Table::markdown() const {
    std::string s = "|";
    for (const auto& h : header) s += " " + cell(h) + " |";
    s += "\n|";
    for (size_t i = 0; i < header.size(); ++i) s += "---|";
    s += "\n";
    for (const auto& row : rows) {
        if (row.size() != header.size())
            throw Error("report table: a row of " + std::to_string(row.size()) +
                        " cells under a header of " + std::to_string(header.size()));
        s += "|";
        for (const auto& c : row) s += " " + cell(c) + " |";
        s += "\n";
    }
    return s + "\n";
}

Report::Report(const Reproduction& r, Quality quality)
    : name_(r.name()), paper_(r.paper()), profile_(r.profile()), quality_(quality) {}

void Report::heading(const std::string& text, int level) {
    md_ << std::string(size_t(std::max(1, level)), '#') << " " << text << "\n\n";
}

void Report::paragraph(const std::string& markdown) { md_ << markdown << "\n\n"; }

void Report::table(const Table& t) { md_ << t.markdown(); }

void Report::figure(const std::string& file, const std::string& caption) {
    md_ << "![" << caption << "](" << file << ")\n\n*" << caption << "*\n\n";
    figures_.push_back({{"file", file}, {"caption", caption}});
}

void Report::claim(Claim c) {
    for (const Claim& o : claims_)
        if (o.id == c.id) throw Error("report: claim '" + c.id + "' given twice");
    claims_.push_back(std::move(c));
}

int Report::claimsHeld() const {
    int n = 0;
    for (const Claim& c : claims_) n += c.holds ? 1 : 0;
    return n;
}

nlohmann::json Report::write(const fs::path& outDir, nlohmann::json results) const {
    fs::create_directories(outDir);
    for (const auto& f : figures_)
        if (!fs::exists(outDir / f["file"].get<std::string>()))
            throw Error("report: figure " + (outDir / f["file"].get<std::string>()).string() +
                        " was not written");

    // ---- results.json: the paper's numbers plus the common keys ---------------------------
    results["name"] = name_;
    results["paper"] = paper_;
    results["profile"] = profile_;
    results["quality"] = qualityName(quality_);
    results["claims"] = nlohmann::json::array();
    for (const Claim& c : claims_) results["claims"].push_back(claimToJson(c));
    results["claims_held"] = claimsHeld();
    results["claims_total"] = int(claims_.size());
    results["figures"] = figures_;

    // ---- report.md: header, the claims, then the paper's own sections --------------------
    std::ostringstream md;
    md << "# " << paper_ << " — reproduction\n\n"
       << "`retroglass reproduce " << name_ << "` on the emulated `" << profile_
       << "` profile, quality `" << qualityName(quality_) << "`. Numbers: `results.json`.\n\n";
    md << "## The paper's claims: " << claimsHeld() << " of " << claims_.size() << " hold\n\n";
    if (claims_.empty()) {
        md << "No claim is checked yet.\n\n";
    } else {
        Table t{{"", "where", "claim", "test", "measured"}, {}};
        for (const Claim& c : claims_)
            t.rows.push_back({c.holds ? "✔ holds" : "✘ does not hold", c.section, c.statement,
                              c.test, measuredText(c.measured)});
        md << t.markdown();
    }
    // ---- the other quality beside this one, when it was run into the same folder --------
    // Each run keeps its results as results-<quality>.json too, so the quick and the paper
    // numbers stand side by side whichever ran last.
    const std::string other = quality_ == Quality::Paper ? "quick" : "paper";
    if (const fs::path otherFile = outDir / ("results-" + other + ".json"); fs::exists(otherFile)) {
        nlohmann::json o;
        try {
            std::ifstream f(otherFile);
            o = nlohmann::json::parse(f);
        } catch (const nlohmann::json::exception& e) {
            throw Error(otherFile.string() + ": " + e.what());
        }
        md << "## Quick and paper quality side by side\n\n"
           << "This run is `" << qualityName(quality_) << "`; the `" << other << "` numbers are "
           << "from `" << otherFile.filename().string() << "`, the last " << other
           << " run into this folder.\n\n";
        const bool paperHere = quality_ == Quality::Paper;
        std::map<std::string, nlohmann::json> otherClaims;
        for (const auto& c : o.value("claims", nlohmann::json::array()))
            otherClaims[c.value("id", "")] = c;
        auto cell = [](const nlohmann::json& c) {
            if (c.is_null()) return std::string("—");
            return std::string(c.value("holds", false) ? "✔ " : "✘ ") +
                   measuredText(c.value("measured", nlohmann::json::object()));
        };
        Table t{{"claim", "quick", "paper"}, {}};
        for (const nlohmann::json& c : results["claims"]) {
            const std::string id = c["id"];
            const nlohmann::json oc = otherClaims.count(id) ? otherClaims[id] : nlohmann::json();
            t.rows.push_back({"`" + id + "`", paperHere ? cell(oc) : cell(c),
                              paperHere ? cell(c) : cell(oc)});
        }
        t.rows.push_back({"claims hold",
                          std::to_string(paperHere ? o.value("claims_held", 0) : claimsHeld()),
                          std::to_string(paperHere ? claimsHeld() : o.value("claims_held", 0))});
        md << t.markdown();
    }
    md << md_.str();
    const std::string markdown = md.str();
    writeFile(outDir / "report.md", markdown);
    writeFile(outDir / "index.html",
              htmlPage(paper_ + " — retroglass",
                       "<p class=\"nav\"><a href=\"../index.html\">← all papers</a> · "
                       "<a href=\"report.md\">report.md</a> · "
                       "<a href=\"results.json\">results.json</a></p>\n" +
                           markdownToHtml(markdown)));
    writeFile(outDir / "results.json", results.dump(2) + "\n");
    writeFile(outDir / ("results-" + std::string(qualityName(quality_)) + ".json"),
              results.dump(2) + "\n");
    return results;
}

std::string markdownToHtml(const std::string& markdown) {
    static std::once_flag once;
    std::call_once(once, [] { cmark_gfm_core_extensions_ensure_registered(); });
    std::unique_ptr<cmark_parser, void (*)(cmark_parser*)> parser(
        cmark_parser_new(CMARK_OPT_DEFAULT), cmark_parser_free);
    for (const char* ext : {"table", "strikethrough", "autolink"})
        if (cmark_syntax_extension* e = cmark_find_syntax_extension(ext))
            cmark_parser_attach_syntax_extension(parser.get(), e);
    cmark_parser_feed(parser.get(), markdown.data(), markdown.size());
    std::unique_ptr<cmark_node, void (*)(cmark_node*)> doc(cmark_parser_finish(parser.get()),
                                                            cmark_node_free);
    char* html = cmark_render_html(doc.get(), CMARK_OPT_DEFAULT,
                                   cmark_parser_get_syntax_extensions(parser.get()));
    std::string out = html ? html : "";
    std::free(html);
    return out;
}

std::string htmlEscape(const std::string& text) {
    std::string out;
    for (char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            default: out += c;
        }
    }
    return out;
}

std::string htmlPage(const std::string& title, const std::string& body) {
    return "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>" +
           htmlEscape(title) +
           "</title>\n<style>\n"
           "body{font-family:system-ui,sans-serif;max-width:72em;margin:2em auto;padding:0 1em;"
           "line-height:1.45;color:#222}\n"
           "img{max-width:100%;border:1px solid #ccc;image-rendering:pixelated}\n"
           "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;"
           "padding:.25em .6em;vertical-align:top}th{background:#f3f3f3}\n"
           "code{background:#f3f3f3;padding:0 .2em}.nav{font-size:90%}\n"
           ".cards{display:grid;grid-template-columns:repeat(auto-fill,minmax(22em,1fr));"
           "gap:1em}.card{border:1px solid #ccc;border-radius:6px;padding:1em}\n"
           ".card img{width:100%;height:12em;object-fit:contain;background:#fafafa}\n"
           ".held{color:#176317;font-weight:bold}.notheld{color:#a11;font-weight:bold}\n"
           ".muted{color:#777}\n"
           "</style></head><body>\n" +
           body + "\n</body></html>\n";
}

std::string claimsLine(const std::string& name, const nlohmann::json& results) {
    const int held = results.value("claims_held", 0), total = results.value("claims_total", 0);
    std::string s = name + ": " + std::to_string(held) + " of " + std::to_string(total) +
                    " claims hold";
    if (results.contains("claims"))
        for (const auto& c : results["claims"])
            if (!c.value("holds", false)) s += "\n    does not hold: " + c.value("id", std::string());
    return s;
}

}  // namespace rg::demos
