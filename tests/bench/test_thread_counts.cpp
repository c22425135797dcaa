// `retroglass bench --threads LIST` (bench/thread_counts.h): the lists it takes, in order,
// and a clear refusal, naming the entry, of every list it must not.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/error.h"
#include "thread_counts.h"

namespace rg::bench {
namespace {

TEST(BenchThreadCounts, TakesAListInTheOrderGiven) {
    EXPECT_EQ(parseThreadCounts("1,2,4,8,16"), (std::vector<int>{1, 2, 4, 8, 16}));
    EXPECT_EQ(parseThreadCounts("3"), (std::vector<int>{3}));
    EXPECT_EQ(parseThreadCounts("16,1"), (std::vector<int>{16, 1}));
    EXPECT_EQ(parseThreadCounts("1024"), (std::vector<int>{kMaxThreadCount}));
}

// The message of the refusal of `list`; empty when it was taken.
std::string refusal(const std::string& list) {
    try {
        parseThreadCounts(list);
    } catch (const Error& e) {
        return e.what();
    }
    return {};
}

TEST(BenchThreadCounts, RefusesEachBadListSayingWhy) {
    const struct {
        const char* list;
        const char* why;
    } cases[] = {
        {"", "empty list"},
        {"0", "0 is out of range"},
        {"1,0", "0 is out of range"},
        {"1025", "1025 is out of range"},
        {"99999999999", "99999999999 is out of range"},  // past int: refused, not wrapped
        {"a,b", "'a' is not a thread count"},
        {"-1", "'-1' is not a thread count"},
        {"2.5", "'2.5' is not a thread count"},
        {" 2", "' 2' is not a thread count"},
        {"2,,3", "empty entry at position 2"},
        {",2", "empty entry at position 1"},
        {"1,2,", "empty entry at position 3"},
        {"1,2,1", "1 is listed twice"},
        {"4,4", "4 is listed twice"},
    };
    for (const auto& c : cases) {
        const std::string message = refusal(c.list);
        EXPECT_NE(message.find(c.why), std::string::npos)
            << "--threads '" << c.list << "' gave: " << (message.empty() ? "(taken)" : message);
        EXPECT_NE(message.find("'" + std::string(c.list) + "'"), std::string::npos) << message;
    }
}

TEST(BenchThreadCounts, DefaultIsOneAndAll) {
    EXPECT_EQ(defaultThreadCounts(1), (std::vector<int>{1}));
    EXPECT_EQ(defaultThreadCounts(8), (std::vector<int>{1, 8}));
    EXPECT_EQ(defaultThreadCounts(0).front(), 1);
    EXPECT_EQ(defaultThreadCounts(0).back(), hardwareThreads());
}

}  // namespace
}  // namespace rg::bench
