// Fuzz target: a prepared take's prepared.json (fvv encode --prepared), the
// file every shard reads first. model.bin goes through the stream's model
// reader, which fuzz_decode covers.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "encoder/encode/prepared_take.h"
#include "fuzz/temp_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& dir = fvv::FuzzTempDir();
  const std::string path = dir + "/prepared.json";
  if (!fvv::WriteFuzzFile(path, data, size)) return 0;
  (void)fvv::LoadPreparedTakeDescription(dir);
  std::remove(path.c_str());
  return 0;
}
