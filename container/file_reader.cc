#include "container/file_reader.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>

#include "container/gop_grid.h"

namespace fvv {

Status MemorySource::Read(uint64_t offset, size_t n, uint8_t* out) {
  if (offset > size_ || n > size_ - offset) return Internal("read past the end of memory source");
  if (n > 0) std::memcpy(out, data_ + offset, n);  // an empty read may have no buffer
  return Status::Ok();
}

StatusOr<std::unique_ptr<FileSource>> FileSource::Open(const std::string& path) {
  FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return IoError("cannot open " + path + ": " + std::strerror(errno));
  // A directory opens too, and reports a size it does not have.
  struct stat st;
  if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
    std::fclose(f);
    return IoError("cannot open " + path + ": not a regular file");
  }
  if (fseeko(f, 0, SEEK_END) != 0) {
    std::fclose(f);
    return IoError("cannot seek in " + path);
  }
  const off_t size = ftello(f);
  if (size < 0) {
    std::fclose(f);
    return IoError("cannot size " + path);
  }
  return std::unique_ptr<FileSource>(new FileSource(f, static_cast<uint64_t>(size), path));
}

FileSource::~FileSource() { std::fclose(f_); }

Status FileSource::Read(uint64_t offset, size_t n, uint8_t* out) {
  if (fseeko(f_, static_cast<off_t>(offset), SEEK_SET) != 0 || std::fread(out, 1, n, f_) != n) {
    return IoError("reading " + path_ + " at offset " + std::to_string(offset) + ": " +
                   (std::ferror(f_) ? std::strerror(errno) : "unexpected end of file"));
  }
  return Status::Ok();
}

StatusOr<std::unique_ptr<FileReader>> FileReader::Open(ByteSource* source,
                                                       FragmentReadOptions options,
                                                       bool require_index) {
  std::unique_ptr<FileReader> r(new FileReader(source, options));
  FVV_RETURN_IF_ERROR(r->ReadHeaderBoxes());
  FVV_RETURN_IF_ERROR(CheckGopSamplesClaim(r->info_.header, options.max_gop_samples));
  if (require_index && !r->info_.has_index && r->info_.header.index_offset == 0) {
    return Unsupported(
        "the stream has no index ('indx'), so its fragments cannot be found without reading "
        "all of it: play it from the start with whole fragments");
  }
  FVV_RETURN_IF_ERROR(r->LoadIndex());
  return r;
}

StatusOr<BoxHeader> FileReader::ReadBoxHeaderAt(uint64_t offset) const {
  const uint64_t size = source_->size();
  uint8_t buf[kMaxBoxHeaderSize];
  const size_t n = static_cast<size_t>(std::min<uint64_t>(kMaxBoxHeaderSize, size - offset));
  FVV_RETURN_IF_ERROR(source_->Read(offset, n, buf));
  FVV_ASSIGN_OR_RETURN(BoxHeader h, ParseBoxHeader(buf, n, offset, "file"));
  if (h.size > size - offset) {
    return Truncated(BoxContext(h) + "box of " + std::to_string(h.size) +
                     " bytes runs past the end of the file (" + std::to_string(size - offset) +
                     " bytes left)");
  }
  return h;
}

Status FileReader::ReadHeaderBoxes() {
  const uint64_t size = source_->size();
  if (size == 0) return Truncated("empty file");
  uint8_t magic[8];
  if (size < 8 || !source_->Read(0, 8, magic).ok() ||
      ByteReader(magic + 4, 4).U32() != box::kFileHeader) {
    return Corrupt("not an fvv file: it does not start with an 'fvvh' box");
  }
  uint64_t offset = 0;
  std::vector<uint8_t> payload;
  while (offset < size) {
    // Past a fast-start index, the first fragment is where it says: the
    // header boxes end there (a reader over fetched ranges needs no byte of
    // the fragment to know it).
    if (info_.has_index && !info_.index.empty() && offset == info_.index[0].offset) break;
    FVV_ASSIGN_OR_RETURN(const BoxHeader h, ReadBoxHeaderAt(offset));
    if (!info_.has_header && h.type != box::kFileHeader) {
      return Corrupt("not an fvv file: it starts with box '" + FourCCString(h.type) +
                     "', not 'fvvh'");
    }
    if (h.type == box::kFragment) break;
    const bool known = h.type == box::kFileHeader || h.type == box::kCameras ||
                       h.type == box::kModel || h.type == box::kMotionParams ||
                       h.type == box::kMetadata || h.type == box::kIndex;
    if (known) {
      const uint64_t cap = MaxTopLevelBoxSize(info_, h.type);
      if (h.size > cap) {
        return LimitExceeded(BoxContext(h) + "size " + std::to_string(h.size) + " exceeds " +
                             std::to_string(cap));
      }
      payload.resize(static_cast<size_t>(h.payload_size()));
      FVV_RETURN_IF_ERROR(source_->Read(offset + h.header_size, payload.size(), payload.data()));
      FVV_RETURN_IF_ERROR(ApplyTopLevelBox(h, payload.data(), &info_));
      if (h.type == box::kIndex) {
        fast_start_ = true;
        if (info_.header.index_offset != offset) {
          return Corrupt(BoxContext(h) + "the header's index_offset " +
                         std::to_string(info_.header.index_offset) + " points elsewhere");
        }
      }
    } else if (h.essential()) {
      return Unsupported(BoxContext(h) + "essential box type unknown to this decoder");
    }
    offset += h.size;
  }
  first_fragment_offset_ = offset;
  return CheckReadyForFragments(info_, offset);
}

Status FileReader::LoadIndex() {
  const FileHeader& hdr = info_.header;
  const uint64_t size = source_->size();
  if (!info_.has_index && hdr.index_offset != 0) {
    if (hdr.index_offset < first_fragment_offset_ || hdr.index_offset >= size) {
      return Corrupt("file header: index_offset " + std::to_string(hdr.index_offset) +
                     " is outside the fragment area");
    }
    FVV_ASSIGN_OR_RETURN(const BoxHeader h, ReadBoxHeaderAt(hdr.index_offset));
    if (h.type != box::kIndex) {
      return Corrupt("file header: index_offset points at box '" + FourCCString(h.type) +
                     "', not 'indx'");
    }
    if (h.size > MaxTopLevelBoxSize(info_, h.type))
      return LimitExceeded(BoxContext(h) + "too large");
    std::vector<uint8_t> payload(static_cast<size_t>(h.payload_size()));
    FVV_RETURN_IF_ERROR(source_->Read(h.offset + h.header_size, payload.size(), payload.data()));
    FVV_RETURN_IF_ERROR(ApplyTopLevelBox(h, payload.data(), &info_));
  }
  if (info_.has_index) {
    index_in_stream_ = true;
    for (size_t i = 0; i < info_.index.size(); ++i) {
      const IndexEntry& e = info_.index[i];
      const std::string entry = "index entry " + std::to_string(i) + " (offset " +
                                std::to_string(e.offset) + ", size " + std::to_string(e.size) + ")";
      if (e.offset < first_fragment_offset_) {
        return Corrupt(entry + " lies before the file's fragments");
      }
      // An entry past the end means the stream stopped early (SPEC.md 10).
      if (e.offset > size || e.size > size - e.offset) {
        return Truncated(entry + ": the file ends at byte " + std::to_string(size));
      }
    }
    return Status::Ok();
  }
  // No index: walk the fragments' box headers (one small read each).
  uint64_t offset = first_fragment_offset_;
  while (offset < size) {
    FVV_ASSIGN_OR_RETURN(const BoxHeader h, ReadBoxHeaderAt(offset));
    if (h.type == box::kFragment) {
      uint8_t buf[kMaxBoxHeaderSize + 12 + 14];
      const size_t n = static_cast<size_t>(std::min<uint64_t>(sizeof(buf), h.payload_size()));
      FVV_RETURN_IF_ERROR(source_->Read(offset + h.header_size, n, buf));
      BoxIterator it(buf, n, offset + h.header_size, "fragment");
      BoxHeader fh;
      const uint8_t* p;
      Status s = it.Next(&fh, &p);
      if (!s.ok() || fh.type != box::kFragmentHeader || fh.payload_size() != 14) {
        return Corrupt(BoxContext(h) + "does not start with a valid 'fghd'");
      }
      ByteReader r(p, 14);
      IndexEntry e;
      r.U32();  // gop_index, checked when the fragment is read
      e.first_frame = r.U32();
      e.frame_count = r.U16();
      e.first_camera = r.U16();
      e.camera_count = r.U16();
      e.offset = offset;
      e.size = h.size;
      if (info_.index.size() >= info_.expected_fragments() && hdr.frame_count != 0) {
        return Corrupt(BoxContext(h) + "more fragments than the header's shape allows");
      }
      if (!info_.index.empty()) {
        const IndexEntry& before = info_.index.back();
        FVV_RETURN_IF_ERROR(CheckSpanOrder(hdr, before.first_frame, before.frame_count,
                                           e.first_frame, e.frame_count, BoxContext(h)));
      }
      info_.index.push_back(e);
    } else if (h.type == box::kIndex) {
      // Walked only when the header names no index: an 'indx' is then not
      // where the header says (the streaming reader says so too).
      return Corrupt(BoxContext(h) + "the header's index_offset is " +
                     std::to_string(hdr.index_offset));
    } else if (h.essential()) {
      return Unsupported(BoxContext(h) + "essential box type unknown to this decoder");
    }
    offset += h.size;
  }
  return CheckEndsAfterWholeSpan(hdr, info_.index.size(), "");
}

StatusOr<FragmentData> FileReader::ReadFragment(size_t i, uint64_t bytes) {
  if (i >= info_.index.size()) {
    return InvalidArgument("fragment " + std::to_string(i) + " of " +
                           std::to_string(info_.index.size()));
  }
  const IndexEntry& e = info_.index[i];
  FVV_ASSIGN_OR_RETURN(const BoxHeader h, ReadBoxHeaderAt(e.offset));
  if (h.type != box::kFragment || h.size != e.size) {
    return Corrupt("index entry " + std::to_string(i) + " points at box '" + FourCCString(h.type) +
                   "' of " + std::to_string(h.size) + " bytes, not a fragment of " +
                   std::to_string(e.size));
  }
  if (h.size > MaxTopLevelBoxSize(info_, h.type)) {
    return LimitExceeded(BoxContext(h) + "fragment larger than the level allows");
  }
  if (options_.max_fragment_bytes != 0 && h.payload_size() > options_.max_fragment_bytes) {
    return LimitExceeded(BoxContext(h) + "fragment of " + std::to_string(h.size) +
                         " bytes, more than this decoder holds (" +
                         std::to_string(options_.max_fragment_bytes) + ")");
  }
  FragmentReadOptions options = options_;
  const uint64_t delivered = bytes == 0 || bytes >= h.size ? h.size : bytes;
  if (delivered < h.size) options.delivered = delivered;
  std::vector<uint8_t> payload(
      static_cast<size_t>(delivered > h.header_size ? delivered - h.header_size : 0));
  FVV_RETURN_IF_ERROR(source_->Read(e.offset + h.header_size, payload.size(), payload.data()));
  FragmentData f;
  FVV_RETURN_IF_ERROR(fvv::ReadFragment(h, payload.data(), info_.header, options, &f));
  if (f.info.gop_index != i || f.info.first_frame != e.first_frame ||
      f.info.frame_count != e.frame_count || f.info.first_camera != e.first_camera ||
      f.info.camera_count != e.camera_count ||
      (f.chunked && index_in_stream_ && e.head_size != f.head_bytes)) {
    return Corrupt("index entry " + std::to_string(i) +
                   " disagrees with the fragment it points at");
  }
  return f;
}

StatusOr<size_t> FileReader::FindFragment(uint32_t frame, uint32_t camera) const {
  const FileHeader& h = info_.header;
  if (camera >= h.camera_count) {
    return InvalidArgument("camera " + std::to_string(camera) + " of " +
                           std::to_string(h.camera_count));
  }
  const uint64_t i = uint64_t{frame / h.gop_frames} * h.camera_groups() + camera / h.gop_cameras;
  if (frame >= h.frame_count || i >= info_.index.size()) {
    return InvalidArgument("frame " + std::to_string(frame) + " is beyond the stream's " +
                           std::to_string(h.frame_count) + " frames");
  }
  return static_cast<size_t>(i);
}

StatusOr<std::vector<BoxHeader>> FileReader::ListTopLevelBoxes() const {
  std::vector<BoxHeader> boxes;
  for (uint64_t offset = 0; offset < source_->size();) {
    FVV_ASSIGN_OR_RETURN(const BoxHeader h, ReadBoxHeaderAt(offset));
    boxes.push_back(h);
    offset += h.size;
  }
  return boxes;
}

}  // namespace fvv
