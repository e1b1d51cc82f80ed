#include "platform/drm_display.h"

#include <drm_fourcc.h>
#include <fcntl.h>
#include <poll.h>
#include <sys/mman.h>
#include <unistd.h>
#include <xf86drm.h>
#include <xf86drmMode.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <system_error>

namespace penumbra::platform {

ScreenFit fitFrame(uint32_t frameWidth, uint32_t frameHeight, uint32_t screenWidth,
                   uint32_t screenHeight) {
  if (frameWidth == 0 || frameHeight == 0 || screenWidth == 0 || screenHeight == 0) {
    throw std::invalid_argument("fitFrame: empty frame or screen");
  }
  ScreenFit fit;
  // The scale is screenWidth/frameWidth or screenHeight/frameHeight, whichever is smaller;
  // compared in integers (a·d <= c·b for a/b <= c/d) so that an exact fit is exact.
  const uint64_t fw = frameWidth, fh = frameHeight, sw = screenWidth, sh = screenHeight;
  if (sw * fh <= sh * fw) {  // width-bound
    fit.width = screenWidth;
    fit.height = static_cast<uint32_t>(std::max<uint64_t>(1, fh * sw / fw));
  } else {
    fit.height = screenHeight;
    fit.width = static_cast<uint32_t>(std::max<uint64_t>(1, fw * sh / fh));
  }
  fit.x = (screenWidth - fit.width) / 2;
  fit.y = (screenHeight - fit.height) / 2;
  // Nearest neighbour at pixel centres: screen pixel i shows frame pixel
  // floor((i + 1/2)·frame/fit), always < frame since i + 1/2 < fit.
  fit.sourceColumn.resize(fit.width);
  for (uint32_t i = 0; i < fit.width; ++i) {
    fit.sourceColumn[i] =
        static_cast<uint32_t>((2 * static_cast<uint64_t>(i) + 1) * fw / (2 * fit.width));
  }
  fit.sourceRow.resize(fit.height);
  for (uint32_t i = 0; i < fit.height; ++i) {
    fit.sourceRow[i] =
        static_cast<uint32_t>((2 * static_cast<uint64_t>(i) + 1) * fh / (2 * fit.height));
  }
  return fit;
}

void blitFrame(const uint8_t* rgba, uint32_t frameWidth, const ScreenFit& fit, uint8_t* screen,
               uint32_t pitch) {
  for (uint32_t y = 0; y < fit.height; ++y) {
    uint8_t* out = screen + size_t(fit.y + y) * pitch + size_t(fit.x) * 4;
    // Scaling up repeats rows: copy the row just written instead of converting it again.
    if (y > 0 && fit.sourceRow[y] == fit.sourceRow[y - 1]) {
      std::memcpy(out, out - pitch, size_t(fit.width) * 4);
      continue;
    }
    const uint8_t* in = rgba + size_t(fit.sourceRow[y]) * frameWidth * 4;
    for (uint32_t x = 0; x < fit.width; ++x) {
      const uint8_t* p = in + size_t(fit.sourceColumn[x]) * 4;
      out[4 * x + 0] = p[2];
      out[4 * x + 1] = p[1];
      out[4 * x + 2] = p[0];
      out[4 * x + 3] = 0xff;
    }
  }
}

namespace {

std::string errnoText(int e) {
  return std::error_code(e, std::generic_category()).message();
}

// One scanout buffer: kernel memory mapped into ours, registered as a framebuffer.
struct DumbBuffer {
  uint32_t handle = 0, pitch = 0, fb = 0;
  uint64_t size = 0;
  uint8_t* pixels = nullptr;
};

}  // namespace

struct DrmDisplay::Impl {
  std::string device;
  int fd = -1;
  uint32_t connector = 0, crtc = 0;
  std::string connectorName;
  drmModeModeInfo mode{};
  drmModeCrtc* saved = nullptr;  // what the CRTC showed before us, put back at the end
  DumbBuffer buffers[2];
  int front = 0;
  bool flipPending = false;
  bool flipsWork = true;  // false: the driver refused a page flip; the mode is set instead
  uint32_t frameWidth = 0, frameHeight = 0;
  ScreenFit fit;

  ~Impl() {
    if (fd < 0) return;
    if (flipPending) waitForFlip(std::chrono::milliseconds(500), false);
    if (saved != nullptr) {
      if (saved->mode_valid) {
        drmModeSetCrtc(fd, saved->crtc_id, saved->buffer_id, saved->x, saved->y, &connector, 1,
                       &saved->mode);
      }
      drmModeFreeCrtc(saved);
    }
    for (DumbBuffer& b : buffers) {
      if (b.pixels != nullptr) munmap(b.pixels, b.size);
      if (b.fb != 0) drmModeRmFB(fd, b.fb);
      if (b.handle != 0) {
        drm_mode_destroy_dumb destroy{};
        destroy.handle = b.handle;
        drmIoctl(fd, DRM_IOCTL_MODE_DESTROY_DUMB, &destroy);
      }
    }
    close(fd);
  }

  // The constructor prefixes "display: ".
  [[noreturn]] void fail(const std::string& why) const {
    throw HardwareUnavailable(device + ": " + why);
  }

  // The first connected connector with a mode, and a CRTC that can drive it; false if the
  // card has no connected screen (a render-only GPU, an unplugged HDMI).
  bool findScreen() {
    drmModeRes* res = drmModeGetResources(fd);
    if (res == nullptr) fail("not a display (KMS) device: " + errnoText(errno));
    bool found = false;
    for (int c = 0; c < res->count_connectors && !found; ++c) {
      drmModeConnector* conn = drmModeGetConnector(fd, res->connectors[c]);
      if (conn == nullptr) continue;
      if (conn->connection == DRM_MODE_CONNECTED && conn->count_modes > 0) {
        mode = conn->modes[0];
        for (int m = 0; m < conn->count_modes; ++m) {
          if (conn->modes[m].type & DRM_MODE_TYPE_PREFERRED) {
            mode = conn->modes[m];
            break;
          }
        }
        crtc = crtcFor(*res, *conn);
        if (crtc != 0) {
          found = true;
          connector = conn->connector_id;
          const char* type = drmModeGetConnectorTypeName(conn->connector_type);
          connectorName = std::string(type ? type : "connector") + "-" +
                          std::to_string(conn->connector_type_id);
        }
      }
      drmModeFreeConnector(conn);
    }
    drmModeFreeResources(res);
    return found;
  }

  // The CRTC the connector's encoder drives now, else the first one an encoder of it can use.
  uint32_t crtcFor(const drmModeRes& res, const drmModeConnector& conn) const {
    if (conn.encoder_id != 0) {
      if (drmModeEncoder* enc = drmModeGetEncoder(fd, conn.encoder_id)) {
        const uint32_t id = enc->crtc_id;
        drmModeFreeEncoder(enc);
        if (id != 0) return id;
      }
    }
    for (int e = 0; e < conn.count_encoders; ++e) {
      drmModeEncoder* enc = drmModeGetEncoder(fd, conn.encoders[e]);
      if (enc == nullptr) continue;
      const uint32_t possible = enc->possible_crtcs;
      drmModeFreeEncoder(enc);
      for (int k = 0; k < res.count_crtcs && k < 32; ++k) {
        if (possible & (1u << k)) return res.crtcs[k];
      }
    }
    return 0;
  }

  void createBuffer(DumbBuffer& b) {
    drm_mode_create_dumb create{};
    create.width = mode.hdisplay;
    create.height = mode.vdisplay;
    create.bpp = 32;
    if (drmIoctl(fd, DRM_IOCTL_MODE_CREATE_DUMB, &create) != 0) {
      fail("cannot create a scanout buffer: " + errnoText(errno));
    }
    b.handle = create.handle;
    b.pitch = create.pitch;
    b.size = create.size;
    const uint32_t handles[4] = {b.handle, 0, 0, 0}, pitches[4] = {b.pitch, 0, 0, 0},
                   offsets[4] = {0, 0, 0, 0};
    if (drmModeAddFB2(fd, mode.hdisplay, mode.vdisplay, DRM_FORMAT_XRGB8888, handles, pitches,
                      offsets, &b.fb, 0) != 0) {
      fail("the driver refuses an XRGB8888 framebuffer: " + errnoText(errno));
    }
    drm_mode_map_dumb map{};
    map.handle = b.handle;
    if (drmIoctl(fd, DRM_IOCTL_MODE_MAP_DUMB, &map) != 0) {
      fail("cannot map a scanout buffer: " + errnoText(errno));
    }
    void* p = mmap(nullptr, b.size, PROT_READ | PROT_WRITE, MAP_SHARED, fd,
                   static_cast<off_t>(map.offset));
    if (p == MAP_FAILED) fail("cannot map a scanout buffer: " + errnoText(errno));
    b.pixels = static_cast<uint8_t*>(p);
    std::memset(b.pixels, 0, b.size);  // the bars are black
  }

  // Waits for the pending flip's event; false if it did not come within `limit`.
  bool waitForFlip(std::chrono::milliseconds limit, bool throwOnError) {
    drmEventContext events{};
    events.version = 2;
    events.page_flip_handler = [](int, unsigned, unsigned, unsigned, void* self) {
      static_cast<Impl*>(self)->flipPending = false;
    };
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (flipPending) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return false;
      pollfd p{fd, POLLIN, 0};
      const int ready = poll(&p, 1, static_cast<int>(left.count()));
      if (ready < 0 && errno == EINTR) continue;
      if (ready <= 0) return false;
      if (drmHandleEvent(fd, &events) != 0 && throwOnError) {
        throw std::runtime_error("display: " + device + ": reading its events failed");
      }
    }
    return true;
  }

  void open(const std::filesystem::path& path) {
    device = path.string();
    fd = ::open(device.c_str(), O_RDWR | O_CLOEXEC);
    if (fd < 0) fail(errnoText(errno));
  }
};

namespace {

// Every card in /dev/dri in name order; the first with a connected screen.
std::unique_ptr<DrmDisplay::Impl> openFirstScreen() {
  const std::filesystem::path dri = "/dev/dri";
  std::vector<std::filesystem::path> cards;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dri, ec)) {
    if (e.path().filename().string().rfind("card", 0) == 0) cards.push_back(e.path());
  }
  if (ec) throw HardwareUnavailable(dri.string() + ": " + ec.message() + " (no display driver)");
  std::sort(cards.begin(), cards.end());
  std::string tried;
  for (const auto& card : cards) {
    auto d = std::make_unique<DrmDisplay::Impl>();
    try {
      d->open(card);
      if (d->findScreen()) return d;
      tried += (tried.empty() ? "" : "; ") + card.string() + ": no connected screen";
    } catch (const HardwareUnavailable& e) {
      tried += (tried.empty() ? "" : "; ") + std::string(e.what());
    }
  }
  throw HardwareUnavailable("no DRM card in /dev/dri with a connected screen (" +
                            (tried.empty() ? std::string("none found") : tried) + ")");
}

}  // namespace

DrmDisplay::DrmDisplay(const std::filesystem::path& device, uint32_t frameWidth,
                       uint32_t frameHeight) {
  try {
    if (device.empty()) {
      impl_ = openFirstScreen();
    } else {
      impl_ = std::make_unique<Impl>();
      impl_->open(device);
      if (!impl_->findScreen()) impl_->fail("no connected screen");
    }
    Impl& d = *impl_;
    d.frameWidth = frameWidth;
    d.frameHeight = frameHeight;
    d.fit = fitFrame(frameWidth, frameHeight, d.mode.hdisplay, d.mode.vdisplay);
    for (DumbBuffer& b : d.buffers) d.createBuffer(b);
    d.saved = drmModeGetCrtc(d.fd, d.crtc);
    if (drmModeSetCrtc(d.fd, d.crtc, d.buffers[0].fb, 0, 0, &d.connector, 1, &d.mode) != 0) {
      d.fail("cannot set the screen's mode (" + errnoText(errno) +
             "): another program (a desktop, another kiosk) holds the display");
    }
  } catch (const HardwareUnavailable& e) {
    throw HardwareUnavailable(std::string("display: ") + e.what());
  }
}

DrmDisplay::~DrmDisplay() = default;

std::string DrmDisplay::description() const {
  return "DRM " + impl_->device + " " + impl_->connectorName + " " +
         std::to_string(impl_->mode.hdisplay) + "x" + std::to_string(impl_->mode.vdisplay);
}

bool DrmDisplay::show(const uint8_t* rgba, uint32_t width, uint32_t height) {
  Impl& d = *impl_;
  if (width != d.frameWidth || height != d.frameHeight) {
    throw std::invalid_argument("display: frame " + std::to_string(width) + "x" +
                                std::to_string(height) + ", the display was set up for " +
                                std::to_string(d.frameWidth) + "x" + std::to_string(d.frameHeight));
  }
  // The back buffer may still be on screen until the last flip has happened. At 30 frames a
  // second on a 60 Hz screen it has long happened; the limit only bounds a stuck driver.
  if (d.flipPending && !d.waitForFlip(std::chrono::milliseconds(1000), true)) {
    throw std::runtime_error("display: " + d.device + ": a page flip did not complete in 1 s");
  }
  const int back = 1 - d.front;
  DumbBuffer& b = d.buffers[back];
  blitFrame(rgba, width, d.fit, b.pixels, b.pitch);
  if (d.flipsWork) {
    if (drmModePageFlip(d.fd, d.crtc, b.fb, DRM_MODE_PAGE_FLIP_EVENT, &d) == 0) {
      d.flipPending = true;
    } else if (errno == EINVAL || errno == ENOSYS || errno == EOPNOTSUPP) {
      d.flipsWork = false;  // a driver without flips: set the mode with the new buffer
    } else {
      throw std::runtime_error("display: " + d.device + ": page flip: " + errnoText(errno));
    }
  }
  if (!d.flipsWork && drmModeSetCrtc(d.fd, d.crtc, b.fb, 0, 0, &d.connector, 1, &d.mode) != 0) {
    throw std::runtime_error("display: " + d.device + ": cannot show a frame: " + errnoText(errno));
  }
  d.front = back;
  return true;
}

}  // namespace penumbra::platform
