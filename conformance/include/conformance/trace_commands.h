// `retroglass replay` and `retroglass conform` (docs/trace-format.md, docs/testing.md).
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace rg::conformance {

// Adds the two subcommands to the program; run() executes whichever was parsed.
class TraceCommands {
  public:
    explicit TraceCommands(CLI::App& app);
    bool parsed() const;
    // `threads` and `path` are the global --threads / --path options.
    int run(int threads, const std::string& path) const;

  private:
    CLI::App* replay_;
    CLI::App* conform_;
    std::string file_, out_, raw_, backend_ = "ours", goldenDir_;
    int pass_ = -1;
};

}  // namespace rg::conformance
