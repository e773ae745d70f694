#include <gtest/gtest.h>
#include "rtd/rtd.h"
TEST(Smoke, ListsAccumulate) { EXPECT_FALSE(rtd::listMethods().empty()); }
