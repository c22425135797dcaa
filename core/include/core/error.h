// Errors raised by every module. Bad input and impossible state are refused with an
// exception whose message names the problem; nothing in retroglass aborts on user input.
#pragma once

#include <stdexcept>
#include <string>

namespace rg {

// Base of every error retroglass raises for bad input or impossible state.
class Error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// Asking a hardware profile for something its machine did not have. Period accuracy means
// this is always an error, never a silent fallback (DEVELOPERS.md, "Period-accurate").
class UnsupportedFeature : public Error {
  public:
    UnsupportedFeature(const std::string& profile, const std::string& feature,
                       const std::string& detail = {})
        : Error("profile '" + profile + "' does not support " + feature +
                (detail.empty() ? std::string() : " (" + detail + ")")),
          profile_(profile),
          feature_(feature) {}
    const std::string& profile() const { return profile_; }
    const std::string& feature() const { return feature_; }

  private:
    std::string profile_, feature_;
};

// A state value outside what the emulated API accepts (an enum out of range, a viewport
// of zero size, a texture stage index past the profile's count, ...).
class InvalidState : public Error {
  public:
    using Error::Error;
};

}  // namespace rg
