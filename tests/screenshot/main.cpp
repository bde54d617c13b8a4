// The screenshot tests' main: Google Test, plus --update-golden (see golden.h).
#include <cstring>

#include <gtest/gtest.h>

#include "golden.h"

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--update-golden") == 0) accelviz::testing::set_update_golden_mode(true);
    return RUN_ALL_TESTS();
}
