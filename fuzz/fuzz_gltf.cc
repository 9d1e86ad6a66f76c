// Fuzz target: the glTF 2.0 character importer (`fvv synth --actor`). Byte 0
// picks the container: .gltf (JSON, buffers as data URIs) or .glb (binary);
// the rest is the file, written to a temporary path because the importer
// reads files.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "encoder/import/gltf.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const std::string dir = [] {
    char tmpl[] = "/tmp/fvv_fuzz_gltf_XXXXXX";
    const char* made = mkdtemp(tmpl);
    return std::string(made ? made : "/tmp");
  }();
  const std::string path = dir + ((data[0] & 1) ? "/actor.glb" : "/actor.gltf");
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return 0;
  std::fwrite(data + 1, 1, size - 1, f);
  std::fclose(f);
  (void)fvv::LoadGltf(path);
  std::remove(path.c_str());
  return 0;
}
