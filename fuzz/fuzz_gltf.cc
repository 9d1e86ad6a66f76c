// Fuzz target: the glTF 2.0 character importer (`fvv synth --actor`). Byte 0
// picks the container: .gltf (JSON, buffers as data URIs) or .glb (binary);
// the rest is the file, written to a temporary path because the importer
// reads files.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "encoder/import/gltf.h"
#include "fuzz/temp_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const std::string path = fvv::FuzzTempDir() + ((data[0] & 1) ? "/actor.glb" : "/actor.gltf");
  if (!fvv::WriteFuzzFile(path, data + 1, size - 1)) return 0;
  (void)fvv::LoadGltf(path);
  std::remove(path.c_str());
  return 0;
}
