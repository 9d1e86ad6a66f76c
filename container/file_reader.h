// Random-access reader over a seekable source (SPEC.md 3.6): reads the header
// boxes, finds the index (through the header's index_offset, or by walking the
// top-level boxes when a stream has none) and reads any fragment on demand.
#ifndef FVV_CONTAINER_FILE_READER_H_
#define FVV_CONTAINER_FILE_READER_H_

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "container/fragment.h"
#include "container/stream_info.h"

namespace fvv {

class ByteSource {
 public:
  virtual ~ByteSource() = default;
  virtual uint64_t size() const = 0;
  // Reads exactly n bytes at offset (the caller keeps offset + n <= size()).
  virtual Status Read(uint64_t offset, size_t n, uint8_t* out) = 0;
};

class MemorySource : public ByteSource {
 public:
  MemorySource(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  uint64_t size() const override { return size_; }
  Status Read(uint64_t offset, size_t n, uint8_t* out) override;

 private:
  const uint8_t* data_;
  size_t size_;
};

class FileSource : public ByteSource {
 public:
  static StatusOr<std::unique_ptr<FileSource>> Open(const std::string& path);
  ~FileSource() override;
  uint64_t size() const override { return size_; }
  Status Read(uint64_t offset, size_t n, uint8_t* out) override;

 private:
  FileSource(FILE* f, uint64_t size, std::string path)
      : f_(f), size_(size), path_(std::move(path)) {}
  FILE* f_;
  uint64_t size_;
  std::string path_;
};

class FileReader {
 public:
  // The source must outlive the reader. `require_index`: a stream without an
  // index is refused (Unsupported) instead of walked fragment by fragment, for
  // sources where each read is a network request.
  static StatusOr<std::unique_ptr<FileReader>> Open(ByteSource* source,
                                                    FragmentReadOptions options = {},
                                                    bool require_index = false);

  const StreamInfo& info() const { return info_; }
  size_t fragment_count() const { return info_.index.size(); }
  // True when the index came from the stream (front or end), false when rebuilt by scanning.
  bool index_in_stream() const { return index_in_stream_; }
  bool fast_start() const { return fast_start_; }
  // Fragment i, from the first `bytes` bytes of its box (0: all of them; a
  // prefix decodes only with texture-chunks, SPEC.md 3.5.1).
  StatusOr<FragmentData> ReadFragment(size_t i, uint64_t bytes = 0);
  // The fragment holding (frame, camera), or LimitExceeded/InvalidArgument.
  StatusOr<size_t> FindFragment(uint32_t frame, uint32_t camera) const;
  // Every top-level box in file order (for `fvv info`).
  StatusOr<std::vector<BoxHeader>> ListTopLevelBoxes() const;

 private:
  FileReader(ByteSource* source, FragmentReadOptions options)
      : source_(source), options_(options) {}
  Status ReadHeaderBoxes();
  Status LoadIndex();
  StatusOr<BoxHeader> ReadBoxHeaderAt(uint64_t offset) const;

  ByteSource* source_;
  FragmentReadOptions options_;
  StreamInfo info_;
  uint64_t first_fragment_offset_ = 0;
  bool index_in_stream_ = false;
  bool fast_start_ = false;
};

}  // namespace fvv

#endif  // FVV_CONTAINER_FILE_READER_H_
