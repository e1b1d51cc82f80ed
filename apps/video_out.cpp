#include "apps/video_out.h"

#include <cstdio>
#include <stdexcept>

namespace penumbra::apps {

cv::VideoWriter openMp4(const std::string& path, double fps, cv::Size size) {
  cv::VideoWriter writer;
  // x264 encodes 4:2:0, so an odd width or height has no H.264 stream.
  const bool evenSize = size.width % 2 == 0 && size.height % 2 == 0;
  if (evenSize && writer.open(path, cv::VideoWriter::fourcc('a', 'v', 'c', '1'), fps, size)) {
    return writer;
  }
  std::fprintf(stderr, "%s: writing MPEG-4 Part 2 (mp4v), which browsers do not play: %s\n",
               path.c_str(),
               evenSize ? "OpenCV has no H.264 encoder here (FFmpeg without libx264)"
                        : "H.264 needs an even width and height");
  if (!writer.open(path, cv::VideoWriter::fourcc('m', 'p', '4', 'v'), fps, size)) {
    throw std::runtime_error(path + ": OpenCV cannot write an MP4 video here");
  }
  return writer;
}

}  // namespace penumbra::apps
