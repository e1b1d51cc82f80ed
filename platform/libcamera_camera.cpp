#include "platform/libcamera_camera.h"

#include <libcamera/libcamera.h>
#include <libcamera/version.h>
#include <time.h>

#include <array>
#include <atomic>
#include <map>
#include <mutex>
#include <optional>
#include <utility>

#include "platform/camera_buffers.h"
#include "platform/frame_slot.h"

namespace penumbra::platform {

namespace lc = libcamera;

namespace {

std::unique_ptr<lc::CameraManager> startManager() {
  auto manager = std::make_unique<lc::CameraManager>();
  if (const int rc = manager->start(); rc != 0) {
    throw HardwareUnavailable("libcamera: the camera manager did not start (error " +
                              std::to_string(rc) + ")");
  }
  return manager;
}

std::string noCameraMessage() {
  return "libcamera: no camera found (is the ribbon cable seated, camera_auto_detect=1 in "
         "config.txt?)";
}

// libcamera 0.5 split "AE off" into ExposureTimeMode and AnalogueGainMode (each Auto or
// Manual); pipelines written for it (Raspberry Pi OS's) offer those and may no longer offer
// AeEnable, which older ones (Debian 12's 0.0.3, Debian 13's 0.4.0) have alone. Compiled
// against 0.5 or later, a camera that offers ExposureTimeMode gets the split controls.
// Compiled here against 0.0.3, 0.4.0 and 0.7.2 (docs/kiosk.md, "libcamera versions").
#if LIBCAMERA_VERSION_MAJOR > 0 || LIBCAMERA_VERSION_MINOR >= 5
#define PENUMBRA_LIBCAMERA_SPLIT_EXPOSURE_MODES 1
#endif

// Whether this camera takes manual exposure as ExposureTimeMode and AnalogueGainMode (else
// AeEnable).
bool offersSplitExposureModes(const lc::ControlInfoMap& offered) {
#ifdef PENUMBRA_LIBCAMERA_SPLIT_EXPOSURE_MODES
  return offered.find(&lc::controls::ExposureTimeMode) != offered.end();
#else
  (void)offered;
  return false;
#endif
}

// `value` for `control` when the camera offers it, else its name to `missing` (when given). A
// request's list checks every id against the camera's controls and logs an error for each one
// it lacks, on every request: a camera without manual exposure (vimc, many UVC webcams) would
// flood the log at the frame rate.
template <typename T, typename V>
void setIfOffered(lc::ControlList& list, const lc::ControlInfoMap& offered,
                  const lc::Control<T>& control, const V& value,
                  std::vector<std::string>* missing) {
  if (offered.find(&control) != offered.end()) {
    list.set(control, value);
  } else if (missing) {
    missing->push_back(control.name());
  }
}

// The fixed controls (AE and AWB off: the bundle's T() holds for this exposure only), those the
// camera offers; the others' names go to `missing` (configure() only: per request it is null).
// `splitModes`: offersSplitExposureModes().
void setFixedControls(lc::ControlList& list, const lc::ControlInfoMap& offered,
                      const kiosk::CameraControls& c, bool splitModes,
                      std::vector<std::string>* missing = nullptr) {
#ifdef PENUMBRA_LIBCAMERA_SPLIT_EXPOSURE_MODES
  if (splitModes) {
    setIfOffered(list, offered, lc::controls::ExposureTimeMode,
                 int32_t{lc::controls::ExposureTimeModeManual}, missing);
    setIfOffered(list, offered, lc::controls::AnalogueGainMode,
                 int32_t{lc::controls::AnalogueGainModeManual}, missing);
  } else {
    setIfOffered(list, offered, lc::controls::AeEnable, false, missing);
  }
#else
  (void)splitModes;
  setIfOffered(list, offered, lc::controls::AeEnable, false, missing);
#endif
  setIfOffered(list, offered, lc::controls::ExposureTime, c.exposureUs, missing);
  setIfOffered(list, offered, lc::controls::AnalogueGain, c.analogueGain, missing);
  setIfOffered(list, offered, lc::controls::ColourGains,
               std::array<float, 2>{c.redGain, c.blueGain}, missing);
  setIfOffered(list, offered, lc::controls::AwbEnable, false, missing);
}

int64_t monotonicNs() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);  // libcamera's (V4L2's) buffer timestamps
  return int64_t{ts.tv_sec} * 1'000'000'000 + ts.tv_nsec;
}

}  // namespace

struct LibcameraCamera::Impl {
  LibcameraOptions options;
  std::unique_ptr<lc::CameraManager> manager;
  std::shared_ptr<lc::Camera> camera;
  std::unique_ptr<lc::CameraConfiguration> config;
  lc::Stream* stream = nullptr;
  kiosk::PixelFormat format = kiosk::PixelFormat::kXrgb8888;
  uint32_t stride = 0;
  std::unique_ptr<lc::FrameBufferAllocator> allocator;
  std::map<const lc::FrameBuffer*, MappedFrameBuffer> mapped;
  std::vector<std::unique_ptr<lc::Request>> requests;
  std::vector<std::string> unsupported;  // fixed controls the camera does not offer
  bool splitExposureModes = false;       // ExposureTimeMode/AnalogueGainMode, not AeEnable

  FrameSlot slot;
  std::atomic<bool> running{false};
  std::atomic<bool> disconnected{false};
  std::atomic<uint64_t> failedRequests{0};
  // Sequences continue across reopen() (the kiosk refuses a frame that is not newer).
  std::atomic<uint64_t> lastSequence{0};
  uint64_t sequenceBase = 0;

  std::mutex controlsMutex;  // applyControls (kiosk thread) vs requeue (libcamera thread)
  kiosk::CameraControls controls;

  // Producer side, touched only on libcamera's thread.
  kiosk::CameraFrame scratch;

  void open();
  void close();
  void configure();
  void onRequestCompleted(lc::Request* request);
  void onDisconnected() {
    disconnected = true;
    slot.close();
  }
};

void LibcameraCamera::Impl::open() {
  const std::vector<std::shared_ptr<lc::Camera>> cameras = manager->cameras();
  if (cameras.empty()) throw HardwareUnavailable(noCameraMessage());
  camera = options.cameraId.empty() ? cameras.front() : manager->get(options.cameraId);
  if (!camera) {
    std::string listed;
    for (const auto& c : cameras) listed += (listed.empty() ? "" : ", ") + c->id();
    throw HardwareUnavailable("libcamera: camera_id '" + options.cameraId +
                              "' is not listed (cameras: " + listed + ")");
  }
  if (camera->acquire() != 0) {
    const std::string id = camera->id();
    camera.reset();
    throw HardwareUnavailable("libcamera: " + id + " is in use by another program");
  }
  try {
    configure();
  } catch (...) {
    close();
    throw;
  }
}

void LibcameraCamera::Impl::configure() {
  const std::string id = camera->id();
  config = camera->generateConfiguration({lc::StreamRole::Viewfinder});
  if (!config || config->empty()) {
    throw HardwareUnavailable("libcamera: " + id + " offers no viewfinder stream");
  }
  const lc::Size want(options.width, options.height);
  lc::StreamConfiguration& sc = config->at(0);
  // XRGB8888 first; YUV420 when the pipeline has no 32-bit RGB output (a Pi's ISP has both);
  // RGB888 (bytes B, G, R: DRM's little-endian [23:0] R:G:B) for pipelines with only 24-bit
  // RGB, such as the vimc test camera's.
  const std::pair<lc::PixelFormat, kiosk::PixelFormat> accepted[] = {
      {lc::formats::XRGB8888, kiosk::PixelFormat::kXrgb8888},
      {lc::formats::YUV420, kiosk::PixelFormat::kYuv420},
      {lc::formats::RGB888, kiosk::PixelFormat::kBgr8}};
  std::optional<kiosk::PixelFormat> chosen;
  for (const auto& [f, kioskFormat] : accepted) {
    sc.pixelFormat = f;
    sc.size = want;
    sc.bufferCount = options.buffers;
    if (config->validate() != lc::CameraConfiguration::Invalid && sc.pixelFormat == f) {
      chosen = kioskFormat;
      break;
    }
  }
  if (!chosen) {
    throw HardwareUnavailable("libcamera: " + id +
                              " offers none of XRGB8888, YUV420 and RGB888 (got " +
                              sc.pixelFormat.toString() + ")");
  }
  if (sc.size != want) {
    throw HardwareUnavailable("libcamera: " + id + " cannot deliver the calibrated " +
                              want.toString() + " (nearest " + sc.size.toString() + ")");
  }
  format = *chosen;
  stride = sc.stride;
  if (camera->configure(config.get()) != 0) {
    throw HardwareUnavailable("libcamera: " + id + ": configure " + sc.toString() + " failed");
  }
  stream = sc.stream();

  allocator = std::make_unique<lc::FrameBufferAllocator>(camera);
  if (allocator->allocate(stream) < 0) {
    throw HardwareUnavailable("libcamera: " + id + ": cannot allocate frame buffers");
  }
  kiosk::CameraControls c;
  {
    std::lock_guard<std::mutex> lock(controlsMutex);
    c = controls;
  }
  const lc::ControlInfoMap& offered = camera->controls();
  splitExposureModes = offersSplitExposureModes(offered);
  uint64_t cookie = 0;
  for (const std::unique_ptr<lc::FrameBuffer>& buffer : allocator->buffers(stream)) {
    std::vector<PlaneRef> planes;
    for (const lc::FrameBuffer::Plane& p : buffer->planes()) {
      planes.push_back({p.fd.get(), p.offset, p.length});
    }
    mapped.emplace(buffer.get(), MappedFrameBuffer(planes));
    std::unique_ptr<lc::Request> request = camera->createRequest(cookie++);
    if (!request || request->addBuffer(stream, buffer.get()) != 0) {
      throw HardwareUnavailable("libcamera: " + id + ": cannot create a capture request");
    }
    setFixedControls(request->controls(), offered, c, splitExposureModes);
    requests.push_back(std::move(request));
  }

  camera->requestCompleted.connect(this, &Impl::onRequestCompleted);
  camera->disconnected.connect(this, &Impl::onDisconnected);
  lc::ControlList start(offered);
  unsupported.clear();
  setFixedControls(start, offered, c, splitExposureModes, &unsupported);
  disconnected = false;
  slot.reopen();
  sequenceBase = lastSequence;
  if (camera->start(&start) != 0) {
    throw HardwareUnavailable("libcamera: " + id + ": start failed");
  }
  running = true;
  for (const std::unique_ptr<lc::Request>& r : requests) {
    if (camera->queueRequest(r.get()) != 0) {
      throw HardwareUnavailable("libcamera: " + id + ": cannot queue a request");
    }
  }
}

void LibcameraCamera::Impl::close() {
  if (camera) {
    if (running.exchange(false)) camera->stop();  // completes the queued requests, cancelled
    camera->requestCompleted.disconnect(this);
    camera->disconnected.disconnect(this);
  }
  requests.clear();
  mapped.clear();  // unmapped before the allocator frees the buffers
  if (allocator && stream) allocator->free(stream);
  allocator.reset();
  config.reset();
  stream = nullptr;
  if (camera) camera->release();
  camera.reset();
  slot.close();
}

void LibcameraCamera::Impl::onRequestCompleted(lc::Request* request) {
  if (request->status() == lc::Request::RequestCancelled || !running) return;
  const lc::Request::BufferMap& buffers = request->buffers();
  const auto it = buffers.find(stream);
  if (it != buffers.end() && it->second->metadata().status == lc::FrameMetadata::FrameSuccess) {
    const lc::FrameBuffer* buffer = it->second;
    const auto m = mapped.find(buffer);
    std::string why;
    if (m != mapped.end() && packFrame(m->second.planes(), format, options.width, options.height,
                                       stride, scratch, why)) {
      scratch.sequence = sequenceBase + buffer->metadata().sequence + 1;
      scratch.captureNs = static_cast<int64_t>(buffer->metadata().timestamp);  // monotonic
      scratch.exposureUs = request->metadata().get(lc::controls::ExposureTime).value_or(0);
      lastSequence = scratch.sequence;
      slot.put(scratch);
    } else {
      ++failedRequests;
    }
  } else {
    ++failedRequests;
  }
  request->reuse(lc::Request::ReuseBuffers);
  {
    std::lock_guard<std::mutex> lock(controlsMutex);
    setFixedControls(request->controls(), camera->controls(), controls, splitExposureModes);
  }
  if (running) camera->queueRequest(request);
}

LibcameraCamera::LibcameraCamera(LibcameraOptions options) : impl_(std::make_unique<Impl>()) {
  if (const std::string why = checkControls(options.controls); !why.empty()) {
    throw std::invalid_argument("camera_controls: " + why);
  }
  impl_->options = std::move(options);
  impl_->controls = impl_->options.controls;
  impl_->manager = startManager();
  try {
    impl_->open();
  } catch (...) {
    impl_->manager->stop();
    throw;
  }
}

LibcameraCamera::~LibcameraCamera() {
  impl_->close();
  impl_->manager->stop();
}

kiosk::GrabStatus LibcameraCamera::grab(int64_t nowNs, kiosk::CameraFrame& out) {
  if (impl_->disconnected || !impl_->camera) return kiosk::GrabStatus::kDisconnected;
  if (!impl_->slot.take(out)) return kiosk::GrabStatus::kNoFrame;
  out.captureNs += nowNs - monotonicNs();  // sensor time → the kiosk's clock
  return kiosk::GrabStatus::kFrame;
}

bool LibcameraCamera::reopen(int64_t nowNs) {
  (void)nowNs;
  impl_->close();
  try {
    impl_->open();
    return true;
  } catch (const HardwareUnavailable&) {
    return false;
  }
}

std::string LibcameraCamera::describe() const {
  std::string d = "libcamera " + (impl_->camera ? impl_->camera->id() : std::string("(closed)")) +
                  ", " + std::to_string(impl_->options.width) + "x" +
                  std::to_string(impl_->options.height) + " " +
                  kiosk::pixelFormatName(impl_->format) + ", exposure " +
                  std::to_string(impl_->options.controls.exposureUs) + " us";
  for (const std::string& u : impl_->unsupported) d += "; no " + u + " control (not fixed)";
  return d;
}

void LibcameraCamera::applyControls(const kiosk::CameraControls& controls) {
  if (const std::string why = checkControls(controls); !why.empty()) {
    throw std::invalid_argument("camera controls: " + why);
  }
  std::lock_guard<std::mutex> lock(impl_->controlsMutex);
  impl_->controls = controls;
}

uint64_t LibcameraCamera::framesOverwritten() const {
  return impl_->slot.overwritten() + impl_->failedRequests;
}

std::vector<std::string> listLibcameraCameras() {
  std::unique_ptr<lc::CameraManager> manager = startManager();
  std::vector<std::string> ids;
  for (const std::shared_ptr<lc::Camera>& c : manager->cameras()) ids.push_back(c->id());
  manager->stop();
  return ids;
}

}  // namespace penumbra::platform
