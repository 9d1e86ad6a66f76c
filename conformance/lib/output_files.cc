// The conformance output as files and hashes: the reference decoder's output
// hashed (the suite's expectations), written to a directory, and a directory
// another decoder wrote, hashed. Apart from reference_output.cc so that the
// decoding builds where these do not (the WebAssembly decoder in Node).
#include <dirent.h>
#include <sys/stat.h>

#include <memory>

#include "codec/base/atomic_file.h"
#include "conformance/lib/reference_output.h"
#include "conformance/lib/sha256.h"
#include "encoder/io/image_io.h"

namespace fvv {

StatusOr<OutputHashes> ReferenceDecodeHashes(const std::vector<uint8_t>& stream,
                                             const ReferenceDecodeOptions& options) {
  OutputHashes hashes;
  FVV_RETURN_IF_ERROR(
      ReferenceDecode(stream.data(), stream.size(), options,
                      [&hashes](const std::string& name, const std::vector<uint8_t>& bytes) {
                        hashes[name] = Sha256Hex(bytes);
                        return Status::Ok();
                      }));
  return hashes;
}

OutputSink DirectorySink(const std::string& dir) {
  return [dir](const std::string& name, const std::vector<uint8_t>& bytes) {
    return WriteFileAtomic(dir + "/" + name, bytes.data(), bytes.size());
  };
}

StatusOr<OutputHashes> HashDirectory(const std::string& dir) {
  std::unique_ptr<DIR, int (*)(DIR*)> d(opendir(dir.c_str()), &closedir);
  if (!d) return IoError("cannot read directory " + dir);
  OutputHashes hashes;
  while (const dirent* entry = readdir(d.get())) {
    const std::string name = entry->d_name;
    const std::string path = dir + "/" + name;
    struct stat st;
    if (stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) continue;
    FVV_ASSIGN_OR_RETURN(const std::vector<uint8_t> bytes,
                         ReadFileBytes(path, kMaxConformanceFileBytes));
    hashes[name] = Sha256Hex(bytes);
  }
  return hashes;
}

}  // namespace fvv
