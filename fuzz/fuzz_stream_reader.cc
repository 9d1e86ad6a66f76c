// Fuzz target: the incremental box parser (container/stream_reader), fed in
// chunks whose size comes from the first input byte.
#include <cstddef>
#include <cstdint>

#include "container/stream_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const size_t chunk = 1 + data[0] % 61;
  ++data;
  --size;
  fvv::StreamReader reader;
  size_t pos = 0;
  for (int guard = 0; guard < 1000000; ++guard) {
    auto e = reader.Next();
    if (!e.ok() || *e == fvv::ReaderEvent::kEnd) break;
    if (*e == fvv::ReaderEvent::kNeedMoreInput) {
      if (pos == size) {
        reader.Finish();
      } else {
        const size_t n = chunk < size - pos ? chunk : size - pos;
        reader.Push(data + pos, n);
        pos += n;
      }
    }
  }
  return 0;
}
