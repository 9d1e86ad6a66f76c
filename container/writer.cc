#include "container/writer.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace fvv {

Status MemorySink::Append(const uint8_t* data, size_t size) {
  bytes_.insert(bytes_.end(), data, data + size);
  return Status::Ok();
}

Status MemorySink::Overwrite(uint64_t offset, const uint8_t* data, size_t size) {
  if (offset + size > bytes_.size()) return Internal("overwrite past the end of the output");
  std::memcpy(bytes_.data() + offset, data, size);
  return Status::Ok();
}

StatusOr<std::unique_ptr<StreamWriter>> StreamWriter::Create(const StreamInfo& info,
                                                             ByteSink* sink) {
  FVV_RETURN_IF_ERROR(ValidateFileHeader(info.header));
  if (info.cameras.size() != info.header.camera_count) {
    return InvalidArgument("writer: " + std::to_string(info.cameras.size()) +
                           " cameras given, the header declares " +
                           std::to_string(info.header.camera_count));
  }
  FVV_RETURN_IF_ERROR(ValidateBodyModel(info.model, &LimitsOf(info.header)));
  FVV_RETURN_IF_ERROR(ValidateMotionParams(info.motion));
  if (info.motion.key_interval > 1 && !(info.header.tools & kToolMotionInterpolation)) {
    return InvalidArgument("writer: motion key interval > 1 needs the motion-interpolation tool");
  }
  if ((info.motion.coder == MotionCoder::kZstd) != ((info.header.tools & kToolMotionZstd) != 0)) {
    return InvalidArgument("writer: the motion-zstd tool bit must match the motion coder");
  }
  if (info.model.quantisation.quantised != ((info.header.tools & kToolQuantisedModel) != 0)) {
    return InvalidArgument("writer: the quantised-model tool bit must match the model's storage");
  }
  if (info.model.quantisation.quantised) {
    const Status grid = ValidateModelQuantisation(info.model.quantisation);
    if (!grid.ok()) return InvalidArgument("writer: model quantisation: " + grid.message());
  }
  for (const auto& kv : info.metadata) {
    if (!IsValidUtf8(kv.first) || !IsValidUtf8(kv.second) || kv.first.size() > 65535 ||
        kv.second.size() > 65535) {
      return InvalidArgument("writer: metadata '" + kv.first + "' is not UTF-8 under 64 KiB");
    }
  }
  std::unique_ptr<StreamWriter> w(new StreamWriter(info, sink));
  w->info_.header.index_offset = 0;
  FVV_RETURN_IF_ERROR(w->WriteHeaderBoxes());
  return w;
}

Status StreamWriter::WriteHeaderBoxes() {
  std::vector<uint8_t> out = WriteFileHeaderBox(info_.header);
  const auto append = [&out](const std::vector<uint8_t>& b) {
    out.insert(out.end(), b.begin(), b.end());
  };
  append(WriteCamerasBox(info_.cameras));
  append(WriteModelBox(info_.model));
  append(WriteMotionParamsBox(info_.motion));
  if (!info_.metadata.empty()) append(WriteMetadataBox(info_.metadata));
  if (info_.header.frame_count != 0) {
    const uint64_t entries = info_.expected_fragments();
    std::vector<IndexEntry> blank(entries);
    const std::vector<uint8_t> reserved = WriteIndexBox(blank, IndexVersion(info_.header.tools));
    reserved_index_offset_ = sink_->size() + out.size();
    append(reserved);
  }
  return sink_->Append(out.data(), out.size());
}

Status StreamWriter::AddFragment(const FragmentData& f) {
  if (finished_) return InvalidArgument("writer: fragment added after Finish()");
  const FileHeader& h = info_.header;
  const uint32_t gop = static_cast<uint32_t>(index_.size());
  if (f.info.gop_index != gop) {
    return InvalidArgument("writer: fragment " + std::to_string(f.info.gop_index) +
                           " given where fragment " + std::to_string(gop) + " is due");
  }
  if (h.frame_count != 0 && gop >= info_.expected_fragments()) {
    return InvalidArgument("writer: more fragments than the header's frame count allows");
  }
  // While the frame count is open (0), the GOP grid still fixes every field but
  // the last span's frame count.
  FVV_ASSIGN_OR_RETURN(const FragmentInfo expected, FragmentInfoFor(h, gop));
  if (f.info.first_frame != expected.first_frame || f.info.first_camera != expected.first_camera ||
      f.info.camera_count != expected.camera_count ||
      (h.frame_count != 0 ? f.info.frame_count != expected.frame_count
                          : f.info.frame_count == 0 || f.info.frame_count > h.gop_frames)) {
    return InvalidArgument("writer: fragment " + std::to_string(gop) +
                           " does not match the header's GOP grid");
  }
  if ((f.info.first_camera == 0) != !f.motion.empty()) {
    return InvalidArgument("writer: motion belongs in (only) the first camera group's fragment");
  }
  if (((h.tools & kToolMasks) != 0) != !f.masks.empty()) {
    return InvalidArgument("writer: masks must be present exactly when the masks tool is declared");
  }
  uint64_t head_bytes = 0;
  const std::vector<uint8_t> bytes =
      WriteFragmentBox(f, (h.tools & kToolTextureChunks) != 0, &head_bytes);
  if (bytes.size() - kMinBoxHeaderSize > LimitsOf(h).max_fragment_bytes) {
    return LimitExceeded("writer: fragment " + std::to_string(gop) + " of " +
                         std::to_string(bytes.size()) + " bytes exceeds level " +
                         std::to_string(h.level) + "'s limit");
  }
  IndexEntry e;
  e.first_frame = f.info.first_frame;
  e.frame_count = f.info.frame_count;
  e.first_camera = f.info.first_camera;
  e.camera_count = f.info.camera_count;
  e.offset = sink_->size();
  e.size = bytes.size();
  e.head_size = (h.tools & kToolTextureChunks) ? head_bytes : 0;
  FVV_RETURN_IF_ERROR(sink_->Append(bytes.data(), bytes.size()));
  index_.push_back(e);
  frames_seen_ = std::max(frames_seen_, f.info.first_frame + f.info.frame_count);
  return Status::Ok();
}

Status StreamWriter::Finish() {
  if (finished_) return Status::Ok();
  finished_ = true;
  FileHeader& h = info_.header;
  if (h.frame_count == 0) {
    if (index_.empty()) return InvalidArgument("writer: a stream needs at least one fragment");
    h.frame_count = frames_seen_;
  }
  if (index_.size() != info_.expected_fragments()) {
    return InvalidArgument("writer: " + std::to_string(index_.size()) + " fragments written, " +
                           std::to_string(info_.expected_fragments()) +
                           " needed for the declared frames and cameras");
  }
  const std::vector<uint8_t> index = WriteIndexBox(index_, IndexVersion(h.tools));
  uint64_t index_offset;
  if (reserved_index_offset_ != 0) {  // fast start: same entry count as reserved
    index_offset = reserved_index_offset_;
    FVV_RETURN_IF_ERROR(sink_->Overwrite(index_offset, index.data(), index.size()));
  } else {
    index_offset = sink_->size();
    FVV_RETURN_IF_ERROR(sink_->Append(index.data(), index.size()));
  }
  ByteWriter patch;
  patch.U32(h.frame_count);
  FVV_RETURN_IF_ERROR(sink_->Overwrite(kHeaderFrameCountPos, patch.bytes().data(), 4));
  ByteWriter offset;
  offset.U64(index_offset);
  return sink_->Overwrite(kHeaderIndexOffsetPos, offset.bytes().data(), 8);
}

class FileWriter::FileSink : public ByteSink {
 public:
  explicit FileSink(FILE* f, std::string path) : f_(f), path_(std::move(path)) {}
  ~FileSink() override {
    if (f_) std::fclose(f_);
  }
  Status Append(const uint8_t* data, size_t size) override {
    if (std::fseek(f_, 0, SEEK_END) != 0 || std::fwrite(data, 1, size, f_) != size) {
      return IoError("writing " + path_ + ": " + std::strerror(errno));
    }
    size_ += size;
    return Status::Ok();
  }
  Status Overwrite(uint64_t offset, const uint8_t* data, size_t size) override {
    if (fseeko(f_, static_cast<off_t>(offset), SEEK_SET) != 0 ||
        std::fwrite(data, 1, size, f_) != size) {
      return IoError("writing " + path_ + ": " + std::strerror(errno));
    }
    return Status::Ok();
  }
  uint64_t size() const override { return size_; }
  Status Close() {
    const bool ok = std::fflush(f_) == 0 && fsync(fileno(f_)) == 0;
    const int err = errno;
    const bool closed = std::fclose(f_) == 0;
    f_ = nullptr;
    if (!ok || !closed) return IoError("writing " + path_ + ": " + std::strerror(err));
    return Status::Ok();
  }

 private:
  FILE* f_;
  std::string path_;
  uint64_t size_ = 0;
};

StatusOr<std::unique_ptr<FileWriter>> FileWriter::Create(const std::string& path,
                                                         const StreamInfo& info) {
  std::unique_ptr<FileWriter> w(new FileWriter());
  w->path_ = path;
  w->temp_path_ = path + ".part-" + std::to_string(getpid());
  FILE* f = std::fopen(w->temp_path_.c_str(), "w+b");
  if (!f) return IoError("cannot create " + w->temp_path_ + ": " + std::strerror(errno));
  w->sink_ = std::make_unique<FileSink>(f, w->temp_path_);
  auto writer = StreamWriter::Create(info, w->sink_.get());
  if (!writer.ok()) return writer.status();  // the destructor removes the temporary file
  w->writer_ = std::move(writer).value();
  return w;
}

FileWriter::~FileWriter() {
  if (!closed_) {
    sink_.reset();
    std::remove(temp_path_.c_str());
  }
}

uint64_t FileWriter::bytes_written() const { return sink_ ? sink_->size() : 0; }

Status FileWriter::Close() {
  if (closed_) return Status::Ok();
  FVV_RETURN_IF_ERROR(writer_->Finish());
  FVV_RETURN_IF_ERROR(sink_->Close());
  if (std::rename(temp_path_.c_str(), path_.c_str()) != 0) {
    return IoError("cannot rename " + temp_path_ + " to " + path_ + ": " + std::strerror(errno));
  }
  closed_ = true;
  return Status::Ok();
}

StatusOr<std::vector<uint8_t>> WriteStreamToMemory(const StreamInfo& info,
                                                   const std::vector<FragmentData>& fragments) {
  MemorySink sink;
  FVV_ASSIGN_OR_RETURN(auto writer, StreamWriter::Create(info, &sink));
  for (const FragmentData& f : fragments) FVV_RETURN_IF_ERROR(writer->AddFragment(f));
  FVV_RETURN_IF_ERROR(writer->Finish());
  return std::move(sink.bytes());
}

}  // namespace fvv
