#include "container/stream_reader.h"

#include "container/gop_grid.h"

namespace fvv {

const char* ReaderEventName(ReaderEvent e) {
  switch (e) {
    case ReaderEvent::kNeedMoreInput:
      return "need-more-input";
    case ReaderEvent::kHeader:
      return "header";
    case ReaderEvent::kCameras:
      return "cameras";
    case ReaderEvent::kModel:
      return "model";
    case ReaderEvent::kMotionParams:
      return "motion-params";
    case ReaderEvent::kMetadata:
      return "metadata";
    case ReaderEvent::kIndex:
      return "index";
    case ReaderEvent::kFragment:
      return "fragment";
    case ReaderEvent::kEnd:
      break;
  }
  return "end";
}

void StreamReader::Push(const uint8_t* data, size_t size) {
  if (skip_ > 0) {  // the rest of an ignored box: drop without buffering
    const size_t n = static_cast<size_t>(std::min<uint64_t>(skip_, size));
    skip_ -= n;
    offset_ += n;
    data += n;
    size -= n;
  }
  if (start_ > 0 && start_ * 2 >= buffer_.size()) {
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<ptrdiff_t>(start_));
    start_ = 0;
  }
  buffer_.insert(buffer_.end(), data, data + size);
}

StatusOr<ReaderEvent> StreamReader::Fail(Status s) {
  error_ = s;
  return s;
}

Status StreamReader::CheckFragmentAgainstIndex(uint64_t offset, uint64_t size) {
  if (!info_.has_index) return Status::Ok();
  const size_t i = seen_.size() - 1;
  if (i >= info_.index.size() || info_.index[i].offset != offset || info_.index[i].size != size ||
      info_.index[i].head_size != seen_[i].head_size) {
    return Corrupt("index entry " + std::to_string(i) +
                   " does not point at the fragment at offset " + std::to_string(offset));
  }
  return Status::Ok();
}

StatusOr<ReaderEvent> StreamReader::Next() {
  if (!error_.ok()) return error_;
  if (ended_) return ReaderEvent::kEnd;
  if (skip_ > 0) {
    if (finished_) return Fail(Truncated("stream ends inside a box it was skipping"));
    return ReaderEvent::kNeedMoreInput;
  }
  const uint8_t* data = buffer_.data() + start_;
  const size_t available = buffer_.size() - start_;
  if (available == 0 && finished_) {
    if (!info_.has_header) return Fail(Truncated("empty stream"));
    Status ready = CheckReadyForFragments(info_, offset_);
    if (!ready.ok()) return Fail(ready);
    if (info_.header.frame_count != 0 && fragments_read_ != info_.expected_fragments()) {
      return Fail(Truncated("stream ends after " + std::to_string(fragments_read_) + " of " +
                            std::to_string(info_.expected_fragments()) + " fragments"));
    }
    Status whole = CheckEndsAfterWholeSpan(info_.header, fragments_read_, "");
    if (!whole.ok()) return Fail(whole);
    if (info_.header.index_offset != 0 && !info_.has_index) {
      return Fail(Truncated("stream ends before the index at offset " +
                            std::to_string(info_.header.index_offset)));
    }
    if (info_.has_index) {
      for (size_t i = 0; i < seen_.size(); ++i) {
        if (info_.index[i].offset != seen_[i].offset || info_.index[i].size != seen_[i].size ||
            info_.index[i].head_size != seen_[i].head_size) {
          return Fail(Corrupt("index entry " + std::to_string(i) + " disagrees with fragment at " +
                              std::to_string(seen_[i].offset)));
        }
      }
    }
    ended_ = true;
    return ReaderEvent::kEnd;
  }
  auto header = ParseBoxHeader(data, available, offset_, "stream");
  if (!header.ok()) {
    if (header.status().code() == StatusCode::kTruncated && !finished_) {
      return ReaderEvent::kNeedMoreInput;
    }
    return Fail(header.status());
  }
  const BoxHeader& b = *header;
  if (!info_.has_header && b.type != box::kFileHeader) {
    return Fail(Corrupt("not an fvv stream: it starts with box '" + FourCCString(b.type) +
                        "', not 'fvvh'"));
  }
  const bool known = b.type == box::kFileHeader || b.type == box::kCameras ||
                     b.type == box::kModel || b.type == box::kMotionParams ||
                     b.type == box::kMetadata || b.type == box::kIndex || b.type == box::kFragment;
  if (!known && info_.has_header) {
    if (b.essential()) {
      return Fail(Unsupported(BoxContext(b) + "essential box type unknown to this decoder"));
    }
    // Skip it without buffering, however large it is.
    const uint64_t in_buffer = std::min<uint64_t>(b.size, available);
    start_ += static_cast<size_t>(in_buffer);
    offset_ += in_buffer;
    skip_ = b.size - in_buffer;
    return Next();
  }
  const uint64_t cap = MaxTopLevelBoxSize(info_, b.type);
  if (b.size > cap) {
    return Fail(LimitExceeded(BoxContext(b) + "size " + std::to_string(b.size) + " exceeds the " +
                              std::to_string(cap) + " bytes this level allows for it"));
  }
  if (b.type == box::kFragment && options_.max_fragment_bytes != 0 &&
      b.payload_size() > options_.max_fragment_bytes) {
    return Fail(LimitExceeded(BoxContext(b) + "size " + std::to_string(b.size) +
                              " exceeds the fragment bytes this decoder holds (" +
                              std::to_string(options_.max_fragment_bytes) + ")"));
  }
  if (available < b.size) {
    if (finished_) {
      return Fail(Truncated(BoxContext(b) + "stream ends " + std::to_string(b.size - available) +
                            " bytes before the end of the box"));
    }
    return ReaderEvent::kNeedMoreInput;
  }
  const uint8_t* payload = data + b.header_size;
  ReaderEvent event;
  if (b.type == box::kFragment) {
    Status s = CheckReadyForFragments(info_, b.offset);
    if (s.ok()) s = ReadFragment(b, payload, info_.header, options_, &fragment_);
    if (s.ok() && fragment_.info.gop_index != fragments_read_) {
      s = Corrupt(BoxContext(b) + "fragment " + std::to_string(fragment_.info.gop_index) +
                  " where fragment " + std::to_string(fragments_read_) + " was due");
    }
    if (s.ok()) {
      IndexEntry e;
      e.offset = b.offset;
      e.size = b.size;
      e.first_frame = fragment_.info.first_frame;
      e.frame_count = fragment_.info.frame_count;
      e.head_size = fragment_.chunked ? static_cast<uint32_t>(fragment_.head_bytes) : 0;
      if (!seen_.empty()) {
        s = CheckSpanOrder(info_.header, seen_.back().first_frame, seen_.back().frame_count,
                           e.first_frame, e.frame_count, BoxContext(b));
      }
      seen_.push_back(e);
      if (s.ok()) s = CheckFragmentAgainstIndex(b.offset, b.size);
    }
    if (!s.ok()) return Fail(s);
    ++fragments_read_;
    event = ReaderEvent::kFragment;
  } else {
    if (b.type != box::kIndex && fragments_read_ > 0) {
      return Fail(Corrupt(BoxContext(b) + "header box after the first fragment"));
    }
    if (b.type == box::kIndex && b.offset != info_.header.index_offset) {
      return Fail(Corrupt(BoxContext(b) + "the header's index_offset is " +
                          std::to_string(info_.header.index_offset)));
    }
    Status s = ApplyTopLevelBox(b, payload, &info_);
    if (s.ok() && b.type == box::kFileHeader) {
      s = CheckGopSamplesClaim(info_.header, options_.max_gop_samples);
    }
    if (!s.ok()) return Fail(s);
    event = b.type == box::kFileHeader     ? ReaderEvent::kHeader
            : b.type == box::kCameras      ? ReaderEvent::kCameras
            : b.type == box::kModel        ? ReaderEvent::kModel
            : b.type == box::kMotionParams ? ReaderEvent::kMotionParams
            : b.type == box::kMetadata     ? ReaderEvent::kMetadata
                                           : ReaderEvent::kIndex;
  }
  start_ += static_cast<size_t>(b.size);
  offset_ += b.size;
  return event;
}

}  // namespace fvv
