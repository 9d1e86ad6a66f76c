#include "encoder/io/image_io.h"

#include <ImfArray.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <png.h>
#include <sys/stat.h>
#include <turbojpeg.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>

namespace fvv {
namespace {

bool EndsWith(const std::string& s, const char* suffix) {
  const size_t n = std::strlen(suffix);
  if (s.size() < n) return false;
  std::string tail = s.substr(s.size() - n);
  std::transform(tail.begin(), tail.end(), tail.begin(), ::tolower);
  return tail == suffix;
}

struct FileCloser {
  void operator()(FILE* f) const {
    if (f) std::fclose(f);
  }
};
using FilePtr = std::unique_ptr<FILE, FileCloser>;

StatusOr<Image> ReadPng(const std::string& path) {
  png_image png;
  std::memset(&png, 0, sizeof(png));
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str()))
    return IoError(path + ": not a readable PNG (" + png.message + ")");
  Image img;
  img.width = png.width;
  img.height = png.height;
  const bool grey = (png.format & PNG_FORMAT_FLAG_COLOR) == 0;
  img.channels = grey ? 1 : 3;
  png.format = grey ? PNG_FORMAT_GRAY : PNG_FORMAT_RGB;
  if (uint64_t{png.width} * png.height > (uint64_t{1} << 28)) {
    png_image_free(&png);
    return IoError(path + ": image of " + std::to_string(png.width) + "x" +
                   std::to_string(png.height) + " is too large");
  }
  img.pixels.resize(PNG_IMAGE_SIZE(png));
  if (!png_image_finish_read(&png, nullptr, img.pixels.data(), 0, nullptr))
    return IoError(path + ": PNG decoding failed (" + png.message + ")");
  return img;
}

StatusOr<Image> ReadExr(const std::string& path) {
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    if (w <= 0 || h <= 0 || int64_t{w} * h > (int64_t{1} << 28))
      return IoError(path + ": EXR data window is empty or too large");
    const Imf::ChannelList& ch = file.header().channels();
    const bool rgb = ch.findChannel("R") && ch.findChannel("G") && ch.findChannel("B");
    const bool grey = !rgb && ch.findChannel("Y");
    if (!rgb && !grey) return IoError(path + ": EXR has neither R, G, B nor Y channels");
    const char* names[3] = {"R", "G", "B"};
    const int nc = rgb ? 3 : 1;
    std::vector<Imf::Array2D<float>> planes(nc);
    Imf::FrameBuffer fb;
    for (int c = 0; c < nc; ++c) {
      planes[c].resizeErase(h, w);
      fb.insert(
          rgb ? names[c] : "Y",
          Imf::Slice(Imf::FLOAT,
                     reinterpret_cast<char*>(&planes[c][0][0] - dw.min.x - int64_t{dw.min.y} * w),
                     sizeof(float), sizeof(float) * w));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    Image img;
    img.width = w;
    img.height = h;
    img.channels = nc;
    img.pixels.resize(size_t{static_cast<uint32_t>(w)} * h * nc);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < nc; ++c) {
          const float v = planes[c][y][x];
          const float clamped = std::isnan(v) ? 0.f : std::min(1.f, std::max(0.f, v));
          img.pixels[(size_t{static_cast<uint32_t>(y)} * w + x) * nc + c] =
              static_cast<uint8_t>(clamped * 255.f + 0.5f);
        }
    return img;
  } catch (const std::exception& e) {
    return IoError(path + ": cannot read EXR (" + e.what() + ")");
  }
}

struct TjCloser {
  void operator()(void* h) const {
    if (h) tjDestroy(h);
  }
};

// Baseline and progressive JPEG, 8-bit, any subsampling, grey kept grey.
// The header is read first, so a claimed size is refused before anything is
// allocated for it; a corrupt stream is an error, not a partly grey picture.
StatusOr<Image> ReadJpeg(const std::string& path) {
  StatusOr<std::vector<uint8_t>> bytes = ReadFileBytes(path, uint64_t{1} << 30);
  if (!bytes.ok()) return bytes.status();
  if (bytes->empty()) return IoError(path + ": empty file, not a JPEG");
  std::unique_ptr<void, TjCloser> tj(tjInitDecompress());
  if (!tj) return IoError(path + ": cannot start the JPEG decoder");
  int w = 0, h = 0, subsampling = 0, colourspace = 0;
  if (tjDecompressHeader3(tj.get(), bytes->data(), static_cast<unsigned long>(bytes->size()), &w,
                          &h, &subsampling, &colourspace) != 0) {
    return IoError(path + ": not a readable JPEG (" + tjGetErrorStr2(tj.get()) + ")");
  }
  if (w <= 0 || h <= 0 || int64_t{w} * h > (int64_t{1} << 28)) {
    return IoError(path + ": JPEG of " + std::to_string(w) + "x" + std::to_string(h) +
                   " is empty or too large");
  }
  Image img;
  img.width = static_cast<uint32_t>(w);
  img.height = static_cast<uint32_t>(h);
  img.channels = colourspace == TJCS_GRAY ? 1 : 3;
  img.pixels.resize(size_t{img.width} * img.height * img.channels);
  // Every warning (a truncated or damaged stream) is an error: a frame with
  // its lower part missing would be read as a person cut in half.
  if (tjDecompress2(tj.get(), bytes->data(), static_cast<unsigned long>(bytes->size()),
                    img.pixels.data(), w, 0, h, img.channels == 1 ? TJPF_GRAY : TJPF_RGB,
                    TJFLAG_ACCURATEDCT | TJFLAG_STOPONWARNING) != 0) {
    return IoError(path + ": JPEG decoding failed (" + tjGetErrorStr2(tj.get()) + ")");
  }
  return img;
}

}  // namespace

StatusOr<Image> ReadImage(const std::string& path) {
  if (access(path.c_str(), R_OK) != 0) return IoError(path + ": " + std::strerror(errno));
  if (EndsWith(path, ".exr")) return ReadExr(path);
  if (EndsWith(path, ".jpg") || EndsWith(path, ".jpeg")) return ReadJpeg(path);
  return ReadPng(path);
}

Status WritePng(const std::string& path, const Image& image) {
  png_image png;
  std::memset(&png, 0, sizeof(png));
  png.version = PNG_IMAGE_VERSION;
  png.width = image.width;
  png.height = image.height;
  png.format = image.channels == 1 ? PNG_FORMAT_GRAY : PNG_FORMAT_RGB;
#ifdef PNG_IMAGE_FLAG_FAST
  // Captures write many large noisy frames: a few percent bigger, several times faster.
  png.flags |= PNG_IMAGE_FLAG_FAST;
#endif
  const std::string tmp = TempNameFor(path);
  if (!png_image_write_to_file(&png, tmp.c_str(), 0, image.pixels.data(), 0, nullptr)) {
    std::remove(tmp.c_str());
    return IoError(path + ": cannot write PNG (" + png.message + ")");
  }
  return CommitTempFile(tmp, path);
}

Status WriteExr(const std::string& path, const Image& image) {
  const std::string tmp = TempNameFor(path);
  try {
    const int w = static_cast<int>(image.width), h = static_cast<int>(image.height);
    const int nc = image.channels;
    Imf::Header header(w, h);
    const char* names[3] = {"R", "G", "B"};
    std::vector<std::vector<float>> planes(nc,
                                           std::vector<float>(size_t{image.width} * image.height));
    for (size_t i = 0; i < planes[0].size(); ++i)
      for (int c = 0; c < nc; ++c) planes[c][i] = image.pixels[i * nc + c] / 255.f;
    Imf::FrameBuffer fb;
    for (int c = 0; c < nc; ++c) {
      const char* name = nc == 1 ? "Y" : names[c];
      header.channels().insert(name, Imf::Channel(Imf::FLOAT));
      fb.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(planes[c].data()),
                                 sizeof(float), sizeof(float) * w));
    }
    Imf::OutputFile file(tmp.c_str(), header);
    file.setFrameBuffer(fb);
    file.writePixels(h);
  } catch (const std::exception& e) {
    std::remove(tmp.c_str());
    return IoError(path + ": cannot write EXR (" + e.what() + ")");
  }
  return CommitTempFile(tmp, path);
}

Status WriteImage(const std::string& path, const Image& image) {
  return EndsWith(path, ".exr") ? WriteExr(path, image) : WritePng(path, image);
}

StatusOr<std::vector<uint8_t>> ReadFileBytes(const std::string& path, uint64_t max_bytes) {
  FilePtr f(std::fopen(path.c_str(), "rb"));
  if (!f) return IoError(path + ": " + std::strerror(errno));
  // A directory or device opens too, and reports a size it does not have.
  struct stat st;
  if (fstat(fileno(f.get()), &st) != 0) return IoError(path + ": " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) return IoError(path + ": not a regular file");
  if (std::fseek(f.get(), 0, SEEK_END) != 0) return IoError(path + ": cannot seek");
  const long size = std::ftell(f.get());
  if (size < 0) return IoError(path + ": cannot determine size");
  if (static_cast<uint64_t>(size) > max_bytes)
    return IoError(path + ": " + std::to_string(size) + " bytes is more than the " +
                   std::to_string(max_bytes) + " allowed");
  std::rewind(f.get());
  std::vector<uint8_t> data(static_cast<size_t>(size));
  if (size > 0 && std::fread(data.data(), 1, data.size(), f.get()) != data.size())
    return IoError(path + ": short read");
  return data;
}

Image MakeContactSheet(const std::vector<Image>& tiles, uint32_t columns) {
  Image sheet;
  if (tiles.empty()) return sheet;
  if (columns == 0) columns = static_cast<uint32_t>(std::ceil(std::sqrt(double(tiles.size()))));
  const uint32_t rows = static_cast<uint32_t>((tiles.size() + columns - 1) / columns);
  uint32_t cell_w = 0, cell_h = 0;
  for (const Image& t : tiles)
    cell_w = std::max(cell_w, t.width), cell_h = std::max(cell_h, t.height);
  sheet.width = columns * cell_w;
  sheet.height = rows * cell_h;
  sheet.channels = 3;
  sheet.pixels.assign(size_t{sheet.width} * sheet.height * 3, 0);
  for (size_t i = 0; i < tiles.size(); ++i) {
    const Image& t = tiles[i];
    const size_t x0 = (i % columns) * size_t{cell_w}, y0 = (i / columns) * size_t{cell_h};
    for (uint32_t y = 0; y < t.height; ++y) {
      for (uint32_t x = 0; x < t.width; ++x) {
        const size_t src = (size_t{y} * t.width + x) * t.channels;
        uint8_t* dst = &sheet.pixels[((y0 + y) * sheet.width + x0 + x) * 3];
        for (int k = 0; k < 3; ++k) dst[k] = t.pixels[src + (t.channels == 3 ? k : 0)];
      }
    }
  }
  return sheet;
}

Status MakeDirectories(const std::string& path) {
  for (size_t i = 1; i <= path.size(); ++i) {
    if (i < path.size() && path[i] != '/') continue;
    const std::string partial = path.substr(0, i);
    if (mkdir(partial.c_str(), 0755) != 0 && errno != EEXIST) {
      return IoError("cannot create directory " + partial + ": " + std::strerror(errno));
    }
  }
  return Status::Ok();
}

}  // namespace fvv
