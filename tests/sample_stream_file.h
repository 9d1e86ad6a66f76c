// Tests that decode a file: a sample stream (conformance/sample) written to the
// test's temporary directory under `name`; its path.
#ifndef FVV_TESTS_SAMPLE_STREAM_FILE_H_
#define FVV_TESTS_SAMPLE_STREAM_FILE_H_

#include <gtest/gtest.h>

#include <string>

#include "conformance/sample/sample_stream.h"
#include "container/writer.h"

namespace fvv {

inline std::string WriteSampleStreamFile(const SampleStreamOptions& options,
                                         const std::string& name) {
  auto s = MakeSampleStream(options);
  EXPECT_TRUE(s.ok()) << s.status().ToString();
  const std::string path = ::testing::TempDir() + "/" + name;
  if (!s.ok()) return path;
  auto w = FileWriter::Create(path, s->info);
  EXPECT_TRUE(w.ok());
  if (!w.ok()) return path;
  for (const auto& fragment : s->fragments) EXPECT_TRUE((*w)->AddFragment(fragment).ok());
  EXPECT_TRUE((*w)->Close().ok());
  return path;
}

}  // namespace fvv

#endif  // FVV_TESTS_SAMPLE_STREAM_FILE_H_
