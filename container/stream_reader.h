// Incremental reader (SPEC.md 3): the caller pushes bytes in chunks of any size
// and pulls events. "Need more input" is a request, not an error; errors are
// pinned status codes with messages naming the box and its offset.
//
//   StreamReader reader;
//   while (have bytes) {
//     reader.Push(chunk, n);
//     for (;;) {
//       StatusOr<ReaderEvent> e = reader.Next();
//       if (!e.ok()) { report e.status(); stop; }
//       if (*e == ReaderEvent::kNeedMoreInput) break;
//       if (*e == ReaderEvent::kFragment) use reader.fragment();
//     }
//   }
//   reader.Finish();  // then Next() until kEnd (or an error: truncated stream)
#ifndef FVV_CONTAINER_STREAM_READER_H_
#define FVV_CONTAINER_STREAM_READER_H_

#include <vector>

#include "codec/base/status.h"
#include "container/fragment.h"
#include "container/stream_info.h"

namespace fvv {

enum class ReaderEvent {
  kNeedMoreInput,
  kHeader,  // info().header is ready
  kCameras,
  kModel,
  kMotionParams,
  kMetadata,
  kIndex,
  kFragment,  // fragment() holds the fragment just read
  kEnd,       // after Finish(): the stream was complete
};
const char* ReaderEventName(ReaderEvent e);

class StreamReader {
 public:
  explicit StreamReader(FragmentReadOptions options = {}) : options_(options) {}
  void Push(const uint8_t* data, size_t size);
  void Finish() { finished_ = true; }  // no more input will come
  StatusOr<ReaderEvent> Next();

  const StreamInfo& info() const { return info_; }
  const FragmentData& fragment() const { return fragment_; }
  FragmentData TakeFragment() { return std::move(fragment_); }
  uint64_t fragments_read() const { return fragments_read_; }
  uint64_t bytes_consumed() const { return offset_; }

 private:
  StatusOr<ReaderEvent> Fail(Status s);
  Status CheckFragmentAgainstIndex(uint64_t offset, uint64_t size);

  FragmentReadOptions options_;
  std::vector<uint8_t> buffer_;
  size_t start_ = 0;     // first unconsumed byte of buffer_
  uint64_t offset_ = 0;  // file offset of buffer_[start_]
  uint64_t skip_ = 0;    // bytes of an ignored box still to drop
  bool finished_ = false;
  Status error_;  // sticky
  bool ended_ = false;
  StreamInfo info_;
  FragmentData fragment_;
  uint64_t fragments_read_ = 0;
  std::vector<IndexEntry> seen_;  // offsets of fragments read, to check an index against
};

}  // namespace fvv

#endif  // FVV_CONTAINER_STREAM_READER_H_
