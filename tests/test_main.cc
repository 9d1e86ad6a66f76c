// The tests' main: each test process writes its temporary files into a
// directory of its own (gtest's TempDir() reads TEST_TMPDIR), removed when the
// process ends, so that runs leave nothing behind in /tmp and parallel tests
// never share a file name. A run with a failure keeps the directory, named on
// stderr, for a look at what the failing test wrote.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  std::string dir;
  const char* base = std::getenv("TMPDIR");
  std::string pattern = std::string(base && *base ? base : "/tmp") + "/fvv_test_XXXXXX";
  if (mkdtemp(pattern.data())) {
    dir = pattern;
    setenv("TEST_TMPDIR", dir.c_str(), 1);
  }
  const int result = RUN_ALL_TESTS();
  if (!dir.empty()) {
    if (result == 0) {
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
    } else {
      std::fprintf(stderr, "test files kept in %s\n", dir.c_str());
    }
  }
  return result;
}
