// A folder for the files one test writes, unique to the test and to its process.
//
// CTest runs each GoogleTest case as its own process and `ctest -j4` runs four at once, so a
// fixed folder shared by two tests (or by two runs of one test, or by two checkouts under
// /tmp) is deleted by one while the other reads it: 2 runs in 15 of `ctest -j4 -R
// '^Environment\.'` failed that way (issue 24, item 5), 9 in 20 at -j9 on two loaded cores.
// Hence
//
//     <build>/test-out/<Suite>.<Test>.<pid>/<name>
//
// in the checkout's own build folder, named by the running test and the process id. Two
// calls with the same name in one test return the same folder, emptied again (the steps of
// one test may share it by keeping the path). A test that passes removes its folders when
// it ends; a failed one keeps them and prints where they are, to be looked at.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

namespace rg::test {

// Whether a passing test's folder goes when the test ends (a failing test keeps it anyway).
enum class Keep { IfFailed, Always };

namespace detail {

// Removes the folders made during a test when it ends without a failure, then their parent
// <Suite>.<Test>.<pid> if nothing kept is left in it. Appended to the GoogleTest listeners
// by the first scratchDir() call (GoogleTest owns it from then on).
class ScratchDirCleaner final : public ::testing::EmptyTestEventListener {
  public:
    void add(const std::filesystem::path& dir) {
        if (std::find(dirs_.begin(), dirs_.end(), dir) == dirs_.end()) dirs_.push_back(dir);
    }
    void OnTestEnd(const ::testing::TestInfo& info) override {
        for (const std::filesystem::path& d : dirs_) {
            if (info.result()->Failed()) {
                std::printf("files of the failed test %s.%s kept in %s\n", info.test_suite_name(),
                            info.name(), d.string().c_str());
            } else {
                std::error_code ec;  // a folder already gone, or one not empty, is no failure
                std::filesystem::remove_all(d, ec);
                std::filesystem::remove(d.parent_path(), ec);
            }
        }
        dirs_.clear();
    }

  private:
    std::vector<std::filesystem::path> dirs_;
};

inline ScratchDirCleaner& scratchDirCleaner() {
    static ScratchDirCleaner* cleaner = [] {
        auto* c = new ScratchDirCleaner;
        ::testing::UnitTest::GetInstance()->listeners().Append(c);
        return c;
    }();
    return *cleaner;
}

// "<Suite>.<Test>.<pid>"; parameterised names ("Inst/Suite", "Case/0") lose their slashes.
inline std::string currentTestFolderName() {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = info ? std::string(info->test_suite_name()) + "." + info->name()
                            : std::string("outside-a-test");
    for (char& c : name)
        if (c == '/') c = '_';
    return name + "." + std::to_string(::getpid());
}

}  // namespace detail

// An empty folder <build>/test-out/<Suite>.<Test>.<pid>/<name> for the running test.
// Keep::Always leaves it after a pass too (a screenshot meant for whoever reads the log).
inline std::filesystem::path scratchDir(const std::string& name, Keep keep = Keep::IfFailed) {
    const std::filesystem::path d = std::filesystem::path(RETROGLASS_BUILD_DIR) / "test-out" /
                                    detail::currentTestFolderName() / name;
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    if (keep == Keep::IfFailed && ::testing::UnitTest::GetInstance()->current_test_info())
        detail::scratchDirCleaner().add(d);
    return d;
}

}  // namespace rg::test
