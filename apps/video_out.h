// The MP4 that `penumbra-sim --video` writes: H.264 ('avc1'), which browsers play, when
// OpenCV's FFmpeg backend has an H.264 encoder (Debian's libopencv-videoio links libavcodec
// with libx264); otherwise MPEG-4 Part 2 ('mp4v'), with one line on stderr saying why.
#pragma once

#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>
#include <string>

namespace penumbra::apps {

// Opens `path` for `size` frames at `fps`; throws std::runtime_error naming the file when
// no codec can write it.
cv::VideoWriter openMp4(const std::string& path, double fps, cv::Size size);

}  // namespace penumbra::apps
