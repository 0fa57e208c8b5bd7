#include "io/formats/images.h"

#include "core/fail.h"
#include "io/base/text.h"
#include "io/formats/output_file.h"

#include <png.h>
#include <tiffio.h>

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <map>
#include <memory>
#include <sstream>

namespace saccade {

namespace {

bool Fail(std::string* error, const std::string& path, const std::string& why) {
  return saccade::Fail(error, path + ": " + why);
}

bool IsTiff(const std::string& path) { return EndsWith(path, ".tif") || EndsWith(path, ".tiff"); }

// Reads any PNG into 8- or 16-bit samples, with libpng's simplified API.
// Pixels an image may have: a header that claims more (a few bytes can) is refused before
// anything is allocated for it.
constexpr std::uint64_t kMaxPixels = 50'000'000;

template <typename T>
bool ReadPng(const std::string& path, std::uint32_t format, int channels, Image<T>* image,
             std::string* error) {
  if (!StatRegularFile(path, "an image", nullptr, error)) return false;
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str()))
    return Fail(error, path, std::string("cannot read PNG: ") + png.message);
  const auto refuse = [&](const std::string& why) {
    png_image_free(&png);
    return Fail(error, path, why);
  };
  if (static_cast<std::uint64_t>(png.width) * png.height > kMaxPixels)
    return refuse("a PNG of " + std::to_string(png.width) + "x" + std::to_string(png.height) +
                  " pixels, more than " + std::to_string(kMaxPixels));
  // Depth is 16-bit grey (millimetres): an 8-bit or a colour image is not depth.
  if (format == PNG_FORMAT_LINEAR_Y &&
      (!(png.format & PNG_FORMAT_FLAG_LINEAR) || (png.format & PNG_FORMAT_FLAG_COLOR)))
    return refuse(std::string("a depth image must be 16-bit grey (millimetres); this one is ") +
                  ((png.format & PNG_FORMAT_FLAG_LINEAR) ? "16" : "8") + "-bit " +
                  ((png.format & PNG_FORMAT_FLAG_COLOR) ? "colour" : "grey"));
  png.format = format;
  image->width = static_cast<int>(png.width);
  image->height = static_cast<int>(png.height);
  image->channels = channels;
  image->data.assign(PNG_IMAGE_SIZE(png) / sizeof(T), 0);
  if (!png_image_finish_read(&png, nullptr, image->data.data(), 0, nullptr)) {
    const std::string why = png.message;
    png_image_free(&png);
    return Fail(error, path, "corrupt PNG: " + why);
  }
  return true;
}

template <typename T>
bool WritePng(const std::string& path, std::uint32_t format, const Image<T>& image,
              std::string* error) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = format;
  // On failure libpng removes the file it began; its message may only say "Write Error", so
  // errno says why (a full disk).
  errno = 0;
  if (!png_image_write_to_file(&png, path.c_str(), 0, image.data.data(), 0, nullptr)) {
    const int why = errno;
    std::string message = std::string("cannot write PNG: ") + png.message;
    if (why != 0 && message.find(std::strerror(why)) == std::string::npos)
      message += std::string(" (") + std::strerror(why) + ")";
    return Fail(error, path, message);
  }
  return true;
}

struct TiffCloser {
  void operator()(TIFF* t) const { TIFFClose(t); }
};

// Reads a strip or tiled TIFF of `bits`-bit samples; keeps the first `keep` channels.
template <typename T>
bool ReadTiff(const std::string& path, int keep, Image<T>* image, std::string* error) {
  if (!StatRegularFile(path, "an image", nullptr, error)) return false;
  TIFFSetErrorHandler(nullptr);
  TIFFSetWarningHandler(nullptr);
  std::unique_ptr<TIFF, TiffCloser> tif(TIFFOpen(path.c_str(), "r"));
  if (!tif) return Fail(error, path, "cannot open as TIFF");
  std::uint32_t w = 0, h = 0;
  std::uint16_t bits = 0, spp = 1;
  TIFFGetField(tif.get(), TIFFTAG_IMAGEWIDTH, &w);
  TIFFGetField(tif.get(), TIFFTAG_IMAGELENGTH, &h);
  TIFFGetFieldDefaulted(tif.get(), TIFFTAG_BITSPERSAMPLE, &bits);
  TIFFGetFieldDefaulted(tif.get(), TIFFTAG_SAMPLESPERPIXEL, &spp);
  if (bits != 8 * sizeof(T))
    return Fail(error, path,
                "expected " + std::to_string(8 * sizeof(T)) + "-bit samples, found " +
                    std::to_string(bits));
  if (keep == 1 ? spp != 1 : (spp < keep || spp > 4))
    return Fail(error, path,
                "expected " + std::string(keep == 1 ? "1 channel" : "3 or 4 channels") +
                    ", found " + std::to_string(spp));
  if (w == 0 || h == 0 || static_cast<std::uint64_t>(w) * h > kMaxPixels)
    return Fail(error, path,
                "a TIFF of " + std::to_string(w) + "x" + std::to_string(h) + " pixels (1 to " +
                    std::to_string(kMaxPixels) + ")");
  if (TIFFIsTiled(tif.get())) return Fail(error, path, "tiled TIFF is not supported");
  // Rows must hold w x spp samples, interleaved: YCbCr's subsampled rows are shorter (a colour
  // TIFF so made was read past its row buffer, found by the image fuzzer), planar ones hold one
  // channel at a time.
  std::uint16_t planar = PLANARCONFIG_CONTIG, photometric = 0;
  TIFFGetFieldDefaulted(tif.get(), TIFFTAG_PLANARCONFIG, &planar);
  TIFFGetField(tif.get(), TIFFTAG_PHOTOMETRIC, &photometric);
  const tmsize_t scanline = TIFFScanlineSize(tif.get());
  if (planar != PLANARCONFIG_CONTIG || photometric == PHOTOMETRIC_YCBCR || scanline <= 0 ||
      static_cast<std::uint64_t>(scanline) < static_cast<std::uint64_t>(w) * spp * sizeof(T))
    return Fail(error, path, "only TIFFs with interleaved, unsubsampled samples are supported");
  image->width = static_cast<int>(w);
  image->height = static_cast<int>(h);
  image->channels = keep;
  image->data.assign(static_cast<std::size_t>(w) * h * keep, 0);
  std::vector<T> row(static_cast<std::size_t>(scanline) / sizeof(T) + spp);
  for (std::uint32_t y = 0; y < h; ++y) {
    if (TIFFReadScanline(tif.get(), row.data(), y, 0) < 0)
      return Fail(error, path, "corrupt TIFF at row " + std::to_string(y));
    for (std::uint32_t x = 0; x < w; ++x)
      for (int c = 0; c < keep; ++c)
        image->data[(static_cast<std::size_t>(y) * w + x) * keep + c] = row[x * spp + c];
  }
  return true;
}

}  // namespace

bool ReadDepthImage(const std::string& path, DepthImage* image, std::string* error) {
  if (IsTiff(path)) return ReadTiff(path, 1, image, error);
  // PNG_FORMAT_LINEAR_Y is 16-bit grey; libpng passes 16-bit grey samples through unchanged.
  return ReadPng(path, PNG_FORMAT_LINEAR_Y, 1, image, error);
}

bool ReadRgbImage(const std::string& path, RgbImage* image, std::string* error) {
  if (IsTiff(path)) return ReadTiff(path, 3, image, error);
  return ReadPng(path, PNG_FORMAT_RGB, 3, image, error);
}

bool WriteDepthPng(const std::string& path, const DepthImage& image, std::string* error) {
  return WritePng(path, PNG_FORMAT_LINEAR_Y, image, error);
}

bool WriteRgbPng(const std::string& path, const RgbImage& image, std::string* error) {
  return WritePng(path, PNG_FORMAT_RGB, image, error);
}

std::vector<std::string> ListDepthImages(const std::string& dir) {
  std::vector<std::string> out;
  for (const auto& path : RegularFilesIn(dir)) {
    const std::string name = std::filesystem::path(path).filename().string();
    const bool image = EndsWith(name, ".png") || IsTiff(name);
    if (image && name.find("depth") != std::string::npos) out.push_back(path);
  }
  return out;
}

std::string RgbPartner(const std::string& depth_path) {
  const std::filesystem::path path(depth_path);
  std::string name = path.filename().string();
  const auto at = name.rfind("depth");
  if (at == std::string::npos) return "";
  name.replace(at, 5, "rgb");
  const std::filesystem::path partner = path.parent_path() / name;
  return PathExists(partner.string()) ? partner.string() : "";
}

namespace {

// A file of "key: number" lines (comments after '#'): only `keys`, each of `required` once.
bool ReadKeyValues(const std::string& path, const char* what,
                   std::initializer_list<const char*> keys,
                   std::initializer_list<const char*> required,
                   std::map<std::string, double>* values, std::string* error) {
  std::ifstream in(path);
  if (!in) return Fail(error, path, std::string("cannot open ") + what);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const auto colon = line.find(':');
    std::istringstream key_in(line.substr(0, colon)),
        value_in(colon == std::string::npos ? "" : line.substr(colon + 1));
    std::string key, rest;
    double value = 0;
    key_in >> key;
    if (colon == std::string::npos || !(value_in >> value) || (value_in >> rest) ||
        !std::isfinite(value))
      return Fail(error, path, "line " + std::to_string(number) + ": expected 'key: number'");
    if (std::none_of(keys.begin(), keys.end(), [&](const char* k) { return key == k; }))
      return Fail(error, path, "line " + std::to_string(number) + ": unknown key '" + key + "'");
    (*values)[key] = value;
  }
  for (const char* key : required)
    if (!values->count(key)) return Fail(error, path, std::string("missing key '") + key + "'");
  return true;
}

const std::initializer_list<const char*> kIntrinsicsKeys = {"fx", "fy",    "cx",
                                                            "cy", "width", "height"};

bool IntrinsicsFrom(const std::string& path, std::map<std::string, double>& values,
                    IntrinsicsFile* k, std::string* error) {
  k->fx = values["fx"];
  k->fy = values["fy"];
  k->cx = values["cx"];
  k->cy = values["cy"];
  if (!(values["width"] >= 1 && values["width"] <= 1 << 16 && values["height"] >= 1 &&
        values["height"] <= 1 << 16 && k->fx > 0 && k->fy > 0))
    return Fail(error, path, "fx and fy must be > 0, width and height 1-65536");
  k->width = static_cast<int>(values["width"]);
  k->height = static_cast<int>(values["height"]);
  return true;
}

}  // namespace

bool ReadIntrinsicsFile(const std::string& path, IntrinsicsFile* k, std::string* error) {
  std::map<std::string, double> values;
  return ReadKeyValues(path, "intrinsics file", kIntrinsicsKeys, kIntrinsicsKeys, &values, error) &&
         IntrinsicsFrom(path, values, k, error);
}

bool ReadColourCameraFile(const std::string& path, ColourCameraFile* c, std::string* error) {
  std::map<std::string, double> values;
  if (!ReadKeyValues(
          path, "colour camera file",
          {"fx", "fy", "cx", "cy", "width", "height", "tx", "ty", "tz", "rx", "ry", "rz"},
          kIntrinsicsKeys, &values, error) ||
      !IntrinsicsFrom(path, values, &c->intrinsics, error))
    return false;
  const char* t[] = {"tx", "ty", "tz"};
  const char* r[] = {"rx", "ry", "rz"};
  for (int i = 0; i < 3; ++i) {
    c->t[i] = values.count(t[i]) ? values[t[i]] : 0.0;
    c->r[i] = values.count(r[i]) ? values[r[i]] : 0.0;
  }
  return true;
}

bool WriteColourCameraFile(const std::string& path, const ColourCameraFile& c, std::string* error) {
  std::ostringstream out;
  out.precision(10);
  const IntrinsicsFile& k = c.intrinsics;
  out << "# the colour camera: pinhole intrinsics of its images (pixels), and its place in the\n"
      << "# depth camera's frame: position tx, ty, tz (metres), rotation vector rx, ry, rz (rad)\n"
      << "fx: " << k.fx << "\nfy: " << k.fy << "\ncx: " << k.cx << "\ncy: " << k.cy
      << "\nwidth: " << k.width << "\nheight: " << k.height << "\ntx: " << c.t[0]
      << "\nty: " << c.t[1] << "\ntz: " << c.t[2] << "\nrx: " << c.r[0] << "\nry: " << c.r[1]
      << "\nrz: " << c.r[2] << "\n";
  return WriteBytes(path, out.str(), error);
}

bool WriteIntrinsicsFile(const std::string& path, const IntrinsicsFile& k, std::string* error) {
  std::ostringstream out;
  out.precision(10);
  out << "# pinhole intrinsics of the depth images in this folder (pixels)\n"
      << "fx: " << k.fx << "\nfy: " << k.fy << "\ncx: " << k.cx << "\ncy: " << k.cy
      << "\nwidth: " << k.width << "\nheight: " << k.height << "\n";
  return WriteBytes(path, out.str(), error);
}

}  // namespace saccade
