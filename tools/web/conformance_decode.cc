// The reference decoder's conformance output (SPEC.md Annex B) as a program
// of the runner's protocol, built natively and, with emscripten, for Node: the
// suite run on the WebAssembly build (fvv conform --decoder), and the two
// timed side by side on the same streams and budgets.
//
//   conformance_decode STREAM OUT_DIR BYTES [--streaming] [--threads N]
//   conformance_decode STREAM - BYTES --repeat N     decode N times, no files;
//                                                    prints the mean ms
// Exit status: 0, or the SPEC.md section 10 code of the stream's error (2..6),
// 1 for a problem of the program's own (an unreadable file, bad arguments).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "conformance/lib/reference_output.h"

namespace {

int Usage() {
  std::fprintf(stderr,
               "usage: conformance_decode STREAM OUT_DIR BYTES [--streaming] [--threads N]\n"
               "       conformance_decode STREAM - BYTES --repeat N\n");
  return 1;
}

bool ReadAll(const char* path, std::vector<uint8_t>* out) {
  FILE* f = std::fopen(path, "rb");
  if (!f) return false;
  uint8_t buf[1 << 16];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof(buf), f)) > 0) out->insert(out->end(), buf, buf + n);
  const bool ok = !std::ferror(f);
  std::fclose(f);
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) return Usage();
  const char* stream_path = argv[1];
  const std::string out_dir = argv[2];
  char* end = nullptr;
  const unsigned long long bytes = std::strtoull(argv[3], &end, 10);
  if (*end != '\0') return Usage();
  fvv::ReferenceDecodeOptions options;
  options.bytes_per_fragment = bytes;
  options.threads = 1;
  int repeat = 0;
  for (int i = 4; i < argc; ++i) {
    if (std::strcmp(argv[i], "--streaming") == 0) {
      options.path = fvv::ReadPath::kStreaming;
    } else if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) {
      options.threads = unsigned(std::atoi(argv[++i]));
    } else if (std::strcmp(argv[i], "--repeat") == 0 && i + 1 < argc) {
      repeat = std::atoi(argv[++i]);
    } else {
      return Usage();
    }
  }
  std::vector<uint8_t> stream;
  if (!ReadAll(stream_path, &stream)) {
    std::fprintf(stderr, "conformance_decode: cannot read %s\n", stream_path);
    return 1;
  }
  if (repeat > 0) {
    const auto start = std::chrono::steady_clock::now();
    size_t files = 0;
    for (int r = 0; r < repeat; ++r) {
      const fvv::Status s =
          fvv::ReferenceDecode(stream.data(), stream.size(), options,
                               [&files](const std::string&, const std::vector<uint8_t>&) {
                                 ++files;
                                 return fvv::Status::Ok();
                               });
      if (!s.ok()) {
        std::fprintf(stderr, "conformance_decode: %s\n", s.ToString().c_str());
        return static_cast<int>(s.code());
      }
    }
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    std::printf("%.3f ms per decode (%d decodes, %zu files each)\n", ms / repeat, repeat,
                files / size_t(repeat));
    return 0;
  }
  const fvv::Status s = fvv::ReferenceDecode(
      stream.data(), stream.size(), options,
      [&out_dir](const std::string& name, const std::vector<uint8_t>& data) {
        const std::string path = out_dir + "/" + name;
        FILE* f = std::fopen(path.c_str(), "wb");
        if (!f) return fvv::IoError("cannot write " + path);
        const bool ok = std::fwrite(data.data(), 1, data.size(), f) == data.size();
        return std::fclose(f) == 0 && ok ? fvv::Status::Ok() : fvv::IoError("cannot write " + path);
      });
  if (!s.ok()) {
    std::fprintf(stderr, "conformance_decode: %s\n", s.ToString().c_str());
    return s.code() == fvv::StatusCode::kIoError ? 1 : static_cast<int>(s.code());
  }
  return 0;
}
