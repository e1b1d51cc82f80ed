#include "platform/sdl_display.h"

#include <SDL2/SDL.h>

#include <stdexcept>

namespace penumbra::platform {

struct SdlDisplay::Impl {
  SDL_Window* window = nullptr;
  SDL_Renderer* renderer = nullptr;
  SDL_Texture* texture = nullptr;
  uint32_t width = 0, height = 0;
  ~Impl() {
    if (texture) SDL_DestroyTexture(texture);
    if (renderer) SDL_DestroyRenderer(renderer);
    if (window) SDL_DestroyWindow(window);
    SDL_QuitSubSystem(SDL_INIT_VIDEO);
  }
};

SdlDisplay::SdlDisplay(uint32_t width, uint32_t height, bool fullscreen)
    : impl_(std::make_unique<Impl>()) {
  if (SDL_InitSubSystem(SDL_INIT_VIDEO) != 0) {
    const std::string why = SDL_GetError();
    impl_.reset();  // nothing to quit
    throw HardwareUnavailable("display: SDL cannot start video (" + why +
                              "); set SDL_VIDEODRIVER=kmsdrm, x11, wayland or offscreen");
  }
  impl_->width = width;
  impl_->height = height;
  // The offscreen driver shows nothing, yet by default SDL backs the window surface with an
  // accelerated texture: an EGL context on Mesa llvmpipe, with its own threads and
  // never-freed driver state (LeakSanitizer and ThreadSanitizer report both, inside Mesa).
  // A plain memory framebuffer is all a headless kiosk needs.
  if (showsNothing()) SDL_SetHint(SDL_HINT_FRAMEBUFFER_ACCELERATION, "0");
  impl_->window = SDL_CreateWindow("penumbra kiosk", SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED,
                                   static_cast<int>(width), static_cast<int>(height),
                                   fullscreen ? SDL_WINDOW_FULLSCREEN_DESKTOP : 0);
  if (impl_->window == nullptr) {
    throw HardwareUnavailable(std::string("display: SDL cannot open a window: ") + SDL_GetError());
  }
  // Software rendering: the kiosk has no GPU to speak of and the frame is ready-made.
  impl_->renderer = SDL_CreateRenderer(impl_->window, -1, SDL_RENDERER_SOFTWARE);
  if (impl_->renderer == nullptr) {
    throw HardwareUnavailable(std::string("display: SDL renderer: ") + SDL_GetError());
  }
  SDL_RenderSetLogicalSize(impl_->renderer, static_cast<int>(width), static_cast<int>(height));
  // ABGR8888 is R, G, B, A in memory on a little-endian CPU: the kiosk's RGBA8.
  impl_->texture =
      SDL_CreateTexture(impl_->renderer, SDL_PIXELFORMAT_ABGR8888, SDL_TEXTUREACCESS_STREAMING,
                        static_cast<int>(width), static_cast<int>(height));
  if (impl_->texture == nullptr) {
    throw HardwareUnavailable(std::string("display: SDL texture: ") + SDL_GetError());
  }
  SDL_ShowCursor(SDL_DISABLE);
}

SdlDisplay::~SdlDisplay() = default;

std::string SdlDisplay::driver() const {
  const char* d = SDL_GetCurrentVideoDriver();
  return d ? d : "none";
}

bool SdlDisplay::showsNothing() const {
  const std::string d = driver();
  return d == "offscreen" || d == "dummy" || d == "evdev";
}

bool SdlDisplay::show(const uint8_t* rgba, uint32_t width, uint32_t height) {
  if (width != impl_->width || height != impl_->height) {
    throw std::invalid_argument("display: frame " + std::to_string(width) + "x" +
                                std::to_string(height) + ", the screen is " +
                                std::to_string(impl_->width) + "x" + std::to_string(impl_->height));
  }
  SDL_Event e;
  bool keepGoing = true;
  while (SDL_PollEvent(&e)) {
    if (e.type == SDL_QUIT) keepGoing = false;
    if (e.type == SDL_KEYDOWN && (e.key.keysym.sym == SDLK_ESCAPE || e.key.keysym.sym == SDLK_q)) {
      keepGoing = false;
    }
  }
  if (SDL_UpdateTexture(impl_->texture, nullptr, rgba, static_cast<int>(width * 4)) != 0 ||
      SDL_RenderClear(impl_->renderer) != 0 ||
      SDL_RenderCopy(impl_->renderer, impl_->texture, nullptr, nullptr) != 0) {
    throw std::runtime_error(std::string("display: SDL: ") + SDL_GetError());
  }
  SDL_RenderPresent(impl_->renderer);
  ++shown_;
  return keepGoing;
}

}  // namespace penumbra::platform
