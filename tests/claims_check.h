// Checks shared by the papers' claims tests (docs/testing.md, "Claims tests"): a claim of
// results.json found by id; a claim asserted to hold; a claim's verdict recomputed from its
// own measured numbers and the margin its test states, so that the evaluation logic is
// checked whether or not the claim holds; an ordering the report states, re-checked on the
// numbers of results.json with a margin written beside it.
#pragma once

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace rg::test {

// The claim `id` of results.json; a failure (and an empty object) when it is missing.
inline nlohmann::json claimById(const nlohmann::json& results, const std::string& id) {
    for (const auto& c : results.at("claims"))
        if (c.at("id").get<std::string>() == id) return c;
    ADD_FAILURE() << "no claim '" << id << "' in results.json";
    return nlohmann::json::object();
}

// Every claim has its section, statement, decision rule and measured numbers (all finite),
// and claims_held counts the ones that hold.
inline void expectEveryClaimReportedWithNumbers(const nlohmann::json& results) {
    int held = 0;
    for (const auto& c : results.at("claims")) {
        for (const char* k : {"id", "section", "statement", "test", "measured", "holds"})
            EXPECT_TRUE(c.contains(k)) << k << " missing: " << c.dump(2);
        const nlohmann::json measured = c.value("measured", nlohmann::json::object());
        EXPECT_FALSE(measured.empty()) << c.dump(2);
        for (const auto& [key, v] : measured.items())
            if (v.is_number()) {
                EXPECT_TRUE(std::isfinite(v.get<double>())) << key << ": " << c.dump(2);
            }
        held += c.value("holds", false) ? 1 : 0;
    }
    EXPECT_EQ(results.at("claims_held").get<int>(), held);
    EXPECT_EQ(results.at("claims_total").get<int>(), int(results.at("claims").size()));
}

// The claim holds (its measured numbers are printed when it does not).
inline void expectHolds(const nlohmann::json& results, const std::string& id) {
    const nlohmann::json c = claimById(results, id);
    EXPECT_TRUE(c.value("holds", false)) << id << " does not hold: " << c.dump(2);
}

// A claimAtLeast claim: measured[a] − measured[b] ≥ margin decides it, the stated test
// names that margin, and the verdict is what the numbers say (held or not).
inline void expectAtLeastVerdict(const nlohmann::json& results, const std::string& id,
                                 const std::string& a, const std::string& b, double margin) {
    const nlohmann::json c = claimById(results, id);
    if (c.empty()) return;
    const auto& m = c.at("measured");
    ASSERT_TRUE(m.contains(a) && m.contains(b)) << id << ": " << c.dump(2);
    const double diff = m.at(a).get<double>() - m.at(b).get<double>();
    EXPECT_EQ(c.at("holds").get<bool>(), diff >= margin)
        << id << ": " << a << " − " << b << " = " << diff << " against the margin " << margin;
    char text[32];
    std::snprintf(text, sizeof text, "≥ %.2f", margin);
    EXPECT_NE(c.at("test").get<std::string>().find(text), std::string::npos)
        << id << ": the test does not state the margin " << text << ": " << c.at("test");
}

// A claimWithin claim: |measured[a] − measured[b]| ≤ tolerance decides it.
inline void expectWithinVerdict(const nlohmann::json& results, const std::string& id,
                                const std::string& a, const std::string& b, double tolerance) {
    const nlohmann::json c = claimById(results, id);
    if (c.empty()) return;
    const auto& m = c.at("measured");
    ASSERT_TRUE(m.contains(a) && m.contains(b)) << id << ": " << c.dump(2);
    const double diff = m.at(a).get<double>() - m.at(b).get<double>();
    EXPECT_EQ(c.at("holds").get<bool>(), std::abs(diff) <= tolerance)
        << id << ": |" << a << " − " << b << "| = " << std::abs(diff) << " against " << tolerance;
    char text[32];
    std::snprintf(text, sizeof text, "≤ %.2f", tolerance);
    EXPECT_NE(c.at("test").get<std::string>().find(text), std::string::npos)
        << id << ": the test does not state the tolerance " << text << ": " << c.at("test");
}

// The claim's measured[key] is the number results.json holds at `pointer` (the claim was
// decided on the reported numbers, not on others).
inline void expectMeasuredIs(const nlohmann::json& results, const std::string& id,
                             const std::string& key, const std::string& pointer, double scale = 1.0) {
    const nlohmann::json c = claimById(results, id);
    if (c.empty()) return;
    ASSERT_TRUE(c.at("measured").contains(key)) << id << ": " << c.dump(2);
    const double reported = scale * results.at(nlohmann::json::json_pointer(pointer)).get<double>();
    EXPECT_NEAR(c.at("measured").at(key).get<double>(), reported, 1e-9 * (1.0 + std::abs(reported)))
        << id << "." << key << " against results.json " << pointer;
}

// An ordering the report states, on the numbers of results.json: a − b ≥ margin.
inline void expectOrdering(const nlohmann::json& results, const std::string& a, const std::string& b,
                           double margin, const std::string& why) {
    const double va = results.at(nlohmann::json::json_pointer(a)).get<double>();
    const double vb = results.at(nlohmann::json::json_pointer(b)).get<double>();
    EXPECT_GE(va - vb, margin) << a << " = " << va << ", " << b << " = " << vb << " (" << why << ")";
}

// The claim's row in report.md: its statement with its verdict, its test and its measured
// numbers (one line of the claims table).
inline void expectRowInReport(const std::filesystem::path& reportMd, const nlohmann::json& results,
                              const std::string& id) {
    const nlohmann::json c = claimById(results, id);
    if (c.empty()) return;
    std::ifstream f(reportMd);
    ASSERT_TRUE(f) << reportMd;
    std::string line, row;
    while (std::getline(f, line))
        if (row.empty() && line.rfind("| ", 0) == 0 &&
            line.find(c.at("statement").get<std::string>()) != std::string::npos)
            row = line;
    ASSERT_FALSE(row.empty()) << id << ": no row in " << reportMd;
    EXPECT_NE(row.find(c.at("holds").get<bool>() ? "✔ holds" : "✘ does not hold"), std::string::npos) << row;
    for (const auto& [key, v] : c.at("measured").items())
        if (v.is_number()) {
            EXPECT_NE(row.find(key + " = "), std::string::npos) << key << " not in: " << row;
        }
}

// The ids of the claims that do not hold.
inline std::vector<std::string> brokenClaims(const nlohmann::json& results) {
    std::vector<std::string> ids;
    for (const auto& c : results.at("claims"))
        if (!c.at("holds").get<bool>()) ids.push_back(c.at("id").get<std::string>());
    return ids;
}

}  // namespace rg::test
