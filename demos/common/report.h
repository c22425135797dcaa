// The shared shape of every reproduction's output (docs/reports.md):
//
//   out/<name>/report.md      the report, Markdown, for tools and for reading as text
//   out/<name>/index.html     the same report as a page a browser shows with its figures
//   out/<name>/results.json   the numbers, with the `claims` array every paper fills
//   out/index.html            the gallery over every paper (gallery.h)
//
// A Report collects Markdown, figures, tables of the paper's numbers beside ours and the
// paper's claims, then writes all three files at once.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "reproduction.h"

namespace rg::demos {

// One qualitative statement of the paper, checked against our measurements.
struct Claim {
    std::string id;          // stable key (lower_snake), e.g. layered_beats_single_between
    std::string section;     // where the paper says it, e.g. "§5" or "Figure 6"
    std::string statement;   // the claim in the paper's terms
    std::string test;        // how we decide it, with its margin, e.g. "a − b ≥ 0.5 dB"
    nlohmann::json measured = nlohmann::json::object();  // the values behind the verdict
    bool holds = false;
};

// "higher is better": `a` beats `b` by at least `margin` (same unit).
Claim claimAtLeast(std::string id, std::string section, std::string statement,
                   const std::string& nameA, double a, const std::string& nameB, double b,
                   double margin, const std::string& unit);
// An equality within a tolerance: |a − b| ≤ tolerance.
Claim claimWithin(std::string id, std::string section, std::string statement,
                  const std::string& nameA, double a, const std::string& nameB, double b,
                  double tolerance, const std::string& unit);

nlohmann::json claimToJson(const Claim& c);

// A Markdown table: header and rows of cells (already formatted).
struct Table {
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
    std::string markdown() const;
};

// Fixed-point text of a number ("—" for NaN, "∞" for infinity).
std::string num(double v, int decimals = 2);

class Report {
  public:
    Report(const Reproduction& reproduction, Quality quality);

    // Free Markdown (GitHub flavour: tables, **bold**, `code`, lists).
    std::ostringstream& md() { return md_; }
    void heading(const std::string& text, int level = 2);
    void paragraph(const std::string& markdown);
    void table(const Table& t);
    // An image file in the output folder (relative path) with its caption; the first
    // figure is the paper's thumbnail in the gallery.
    void figure(const std::string& file, const std::string& caption);
    void claim(Claim c);
    const std::vector<Claim>& claims() const { return claims_; }
    int claimsHeld() const;

    // Writes report.md and index.html into outDir, and results.json with `results` plus the
    // common keys (name, paper, profile, quality, claims, claims_held, claims_total,
    // figures). Returns the results as written.
    nlohmann::json write(const std::filesystem::path& outDir, nlohmann::json results) const;

  private:
    std::string name_, paper_, profile_;
    Quality quality_;
    std::ostringstream md_;
    std::vector<Claim> claims_;
    nlohmann::json figures_ = nlohmann::json::array();
};

// Markdown → HTML (cmark-gfm with its table extension), the body of a page.
std::string markdownToHtml(const std::string& markdown);
// A whole page: title, the shared style sheet, `body` (HTML).
std::string htmlPage(const std::string& title, const std::string& body);
// Text for HTML: & < > " escaped.
std::string htmlEscape(const std::string& text);

// The line `retroglass reproduce` prints: "<name>: N of M claims hold".
std::string claimsLine(const std::string& name, const nlohmann::json& results);

}  // namespace rg::demos
