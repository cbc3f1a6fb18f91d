#include <gtest/gtest.h>
#include <pmslam/LogReader.h>
TEST(X,Y){}
