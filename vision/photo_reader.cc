#include "vision/photo_reader.h"

#include <libheif/heif.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <opencv2/imgproc.hpp>

#include "util/input_error.h"
#include "util/input_file.h"
#include "vision/image_codec.h"

namespace softbench {
namespace {

std::string Extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  return ext;
}

// libheif's objects, released however the decoding ends.
struct HeifDeleter {
  void operator()(heif_context* c) const { heif_context_free(c); }
  void operator()(heif_image_handle* h) const { heif_image_handle_release(h); }
  void operator()(heif_image* i) const { heif_image_release(i); }
};

cv::Mat ReadHeif(const std::string& path) {
  const auto fail = [&](const heif_error& error) {
    throw InputError(path + ": not a readable HEIC/HEIF photo (" +
                     error.message + "); export it as JPEG");
  };
  std::unique_ptr<heif_context, HeifDeleter> context(heif_context_alloc());
  heif_error error =
      heif_context_read_from_file(context.get(), path.c_str(), nullptr);
  if (error.code != heif_error_Ok) fail(error);
  heif_image_handle* raw_handle = nullptr;
  error = heif_context_get_primary_image_handle(context.get(), &raw_handle);
  if (error.code != heif_error_Ok) fail(error);
  std::unique_ptr<heif_image_handle, HeifDeleter> handle(raw_handle);
  heif_image* raw_image = nullptr;
  error = heif_decode_image(handle.get(), &raw_image, heif_colorspace_RGB,
                            heif_chroma_interleaved_RGB, nullptr);
  if (error.code != heif_error_Ok) fail(error);
  std::unique_ptr<heif_image, HeifDeleter> image(raw_image);
  int stride = 0;
  const uint8_t* plane = heif_image_get_plane_readonly(
      image.get(), heif_channel_interleaved, &stride);
  const int width = heif_image_get_width(image.get(), heif_channel_interleaved);
  const int height =
      heif_image_get_height(image.get(), heif_channel_interleaved);
  if (plane == nullptr || width <= 0 || height <= 0) {
    throw InputError(path +
                     ": the HEIC/HEIF photo has no picture; export it "
                     "as JPEG");
  }
  const cv::Mat rgb(height, width, CV_8UC3, const_cast<uint8_t*>(plane),
                    static_cast<size_t>(stride));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  return bgr;
}

}  // namespace

bool IsPhotoPath(const std::string& path) {
  const std::string ext = Extension(path);
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".heic" ||
         ext == ".heif";
}

cv::Mat ReadPhoto(const std::string& path) {
  CheckInputFile(path, "the photo");
  const std::string ext = Extension(path);
  if (ext == ".heic" || ext == ".heif") return ReadHeif(path);
  ImageRead read = ReadImageFile(path, ImageColor::kBgr);
  if (read.image.empty()) {
    throw InputError(path + ": " + read.why_not + "; re-export it");
  }
  return read.image;
}

}  // namespace softbench
