// Streaming writer of .fvv files (SPEC.md 3): header boxes first, then fragments
// as the encoder produces them (nothing is held back, so memory stays bounded),
// then the index. Output goes to a temporary file next to the target and is
// renamed over it only by a successful Close(): a crash or an error never
// leaves a half-written file under the final name.
//
// Fast start: when the header gives the frame count, the writer reserves the
// index right after the header boxes and fills it in at Close(), so a player
// can seek before it has seen any fragment. Otherwise the index goes at the end.
#ifndef FVV_CONTAINER_WRITER_H_
#define FVV_CONTAINER_WRITER_H_

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "codec/base/status.h"
#include "container/fragment.h"
#include "container/stream_info.h"

namespace fvv {

// Where the writer's bytes go: a file, or memory (tests, fuzzing, embedding).
class ByteSink {
 public:
  virtual ~ByteSink() = default;
  virtual Status Append(const uint8_t* data, size_t size) = 0;
  virtual Status Overwrite(uint64_t offset, const uint8_t* data, size_t size) = 0;
  virtual uint64_t size() const = 0;
};

class MemorySink : public ByteSink {
 public:
  Status Append(const uint8_t* data, size_t size) override;
  Status Overwrite(uint64_t offset, const uint8_t* data, size_t size) override;
  uint64_t size() const override { return bytes_.size(); }
  std::vector<uint8_t>& bytes() { return bytes_; }

 private:
  std::vector<uint8_t> bytes_;
};

class StreamWriter {
 public:
  // Validates `info` (header limits, camera count, model, motion parameters,
  // metadata) and writes the header boxes. `info.index` is ignored.
  static StatusOr<std::unique_ptr<StreamWriter>> Create(const StreamInfo& info, ByteSink* sink);

  // Fragments in GOP index order (time span, then camera group).
  Status AddFragment(const FragmentData& fragment);
  // Writes or fills in the index and patches the header.
  Status Finish();

  uint64_t fragments_written() const { return index_.size(); }
  bool fast_start() const { return reserved_index_offset_ != 0; }

 private:
  StreamWriter(const StreamInfo& info, ByteSink* sink) : info_(info), sink_(sink) {}
  Status WriteHeaderBoxes();

  StreamInfo info_;
  ByteSink* sink_;
  uint64_t reserved_index_offset_ = 0;
  uint32_t frames_seen_ = 0;
  std::vector<IndexEntry> index_;
  bool finished_ = false;
};

// A StreamWriter onto a temporary file that becomes `path` on Close().
class FileWriter {
 public:
  static StatusOr<std::unique_ptr<FileWriter>> Create(const std::string& path,
                                                      const StreamInfo& info);
  ~FileWriter();  // without Close(): removes the temporary file
  Status AddFragment(const FragmentData& fragment) { return writer_->AddFragment(fragment); }
  Status Close();
  uint64_t bytes_written() const;
  const std::string& path() const { return path_; }

 private:
  class FileSink;
  FileWriter() = default;
  std::string path_, temp_path_;
  std::unique_ptr<FileSink> sink_;
  std::unique_ptr<StreamWriter> writer_;
  bool closed_ = false;
};

// Whole stream in memory (tests, fuzz seeds, conformance generation).
StatusOr<std::vector<uint8_t>> WriteStreamToMemory(const StreamInfo& info,
                                                   const std::vector<FragmentData>& fragments);

}  // namespace fvv

#endif  // FVV_CONTAINER_WRITER_H_
