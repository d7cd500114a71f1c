// igi-view: an interactive window on the IGI pipeline. Renders a glTF scene or the built-in
// Cornell box continuously; the camera, the light and the settings change at a key press. Temporal
// reuse averages each pixel's history of 32 frames across camera motion; with `--temporal 0` (or
// the T key) a still view converges by progressive accumulation of new VPL sets instead and
// restarts at any change. `--frames N` makes it a
// fixed-length (testable) run, `--animate` moves the light or camera, `--play` plays the file's
// own animation (K plays and pauses it, [ and ] step through it), `--screenshot` saves what the
// window shows.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <SDL.h>

#include "common/backend_choice.hpp"
#include "common/command_line.hpp"
#include "common/program_options.hpp"
#include "common/stop_signals.hpp"

#include "igi/backends/embree/embree_backend.hpp"
#include "igi/backends/reference/reference_backend.hpp"
#include "igi/backends/saarcor/saarcor_backend.hpp"
#include "igi/io/image_files.hpp"
#include "common/importance_sampler.hpp"
#include "igi/render/animation.hpp"
#include "igi/render/filter_choice.hpp"
#include "igi/render/renderer.hpp"
#include "igi/scene/animation_sampling.hpp"
#include "igi/scene/camera.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/gltf_material_shader.hpp"

#include "view_controls.hpp"

namespace {

using igi::programs::UsageError;

/// The backends and packet widths the viewer can switch to (each one is a separate Renderer
/// type), in the cycle of the B key, widest first; the viewer starts at igi::native_packet_width.
using ViewBackends = igi::programs::BackendList<igi::EmbreeBackend<16>, igi::EmbreeBackend<8>, igi::EmbreeBackend<4>,
                                                igi::EmbreeBackend<1>, igi::ReferenceBackend<8>, igi::SaarcorBackend>;
/// The cycle of the B key as names and widths.
constexpr auto backend_choices = igi::programs::backend_choices(ViewBackends{});
/// Filters of the F key.
constexpr const char* filter_choices[] = {"discontinuity", "box", "none", "atrous"};
/// Anti-aliasing factors of the N key.
constexpr int antialiasing_choices[] = {1, 2, 4};
/// Frames one turn of the animated light (or camera) takes: 4 s at 30 fps.
constexpr int animation_period = 120;
/// Seconds of the file's animation per frame while it plays: 30 frames a second, as the light's
/// turn; a fixed step (not the clock) keeps each frame a function of its number, as in igi-render.
constexpr double play_step = 1.0 / 30.0;
/// Seconds one [ or ] key press moves the file's animation: three frames' worth, a visible step.
constexpr double scrub_step = 0.1;

/// A Renderer of any backend type behind one interface, so the B key can swap backends.
class ViewRenderer {
 public:
  virtual ~ViewRenderer() = default;
  /// Renders frame `index` seen by `camera`.
  virtual igi::Frame render(const igi::Camera& camera, std::uint32_t index) = 0;
  /// Moves instance `instance`.
  virtual void set_instance_transform(int instance, const glm::mat4& transform) = 0;
  /// Replaces punctual light `light`.
  virtual void set_light(int light, const igi::PunctualLight& value) = 0;
  /// Applies an animation's scene changes (the camera in them is the caller's business).
  virtual void apply(const igi::SceneChanges& changes) = 0;
  /// Frames before the last one with the same view and scene (with temporal reuse; else 0).
  virtual int still_frames() const = 0;
};

/// The Renderer over backend B with the glTF materials, the standard BRDF and the chosen VPL sampler.
template <class B>
class TypedViewRenderer final : public ViewRenderer {
 public:
  /// A renderer of `scene` (borrowed, must outlive it) with `settings`, the filter named `filter`
  /// and the VPL sampler named `vpl_sampler`.
  TypedViewRenderer(igi::Scene& scene, const igi::RenderSettings& settings, const std::string& filter,
                    const std::string& vpl_sampler)
      : surface_(scene), sampler_(vpl_sampler), filter_(filter),
        renderer_(scene, settings, surface_, brdf_, sampler_, filter_) {}
  igi::Frame render(const igi::Camera& camera, std::uint32_t index) override { return renderer_.render(camera, index); }
  void set_instance_transform(int instance, const glm::mat4& transform) override {
    renderer_.set_instance_transform(instance, transform);
  }
  void set_light(int light, const igi::PunctualLight& value) override { renderer_.set_light(light, value); }
  void apply(const igi::SceneChanges& changes) override { static_cast<void>(renderer_.apply(changes)); }
  int still_frames() const override { return renderer_.temporal() ? renderer_.temporal()->still_frames() : 0; }

 private:
  // The renderer borrows the policies: they are declared (so built) before it.
  igi::GltfMaterialShader surface_;
  igi::StandardBrdf brdf_;
  igi::programs::ProgramVplSampler sampler_;
  igi::FilterChoice filter_;
  igi::Renderer<B, igi::GltfMaterialShader, igi::StandardBrdf, igi::programs::ProgramVplSampler, igi::FilterChoice> renderer_;
};

/// A renderer for `choice`.
std::unique_ptr<ViewRenderer> make_renderer(const igi::programs::BackendChoice& choice, igi::Scene& scene,
                                            const igi::RenderSettings& settings, const std::string& filter,
                                            const std::string& vpl_sampler) {
  return igi::programs::with_backend_of(ViewBackends{}, choice.backend, choice.packet,
                                        [&]<class B>() -> std::unique_ptr<ViewRenderer> {
                                          return std::make_unique<TypedViewRenderer<B>>(scene, settings, filter,
                                                                                        vpl_sampler);
                                        });
}

/// Everything the command line decides.
struct Options : igi::programs::SceneOptions {
  std::string size = "640x480";          ///< WIDTHxHEIGHT as typed.
  std::string filter = "discontinuity";  ///< Filter at the start (the F key cycles).
  std::string vpl_sampler = "qmc";       ///< VPL sampler.
  std::string backend = "embree";        ///< Backend at the start (the B key cycles).
  std::string animate = "none";          ///< What moves from the first frame: none, light or camera.
  std::string screenshot;                ///< PNG of the last of --frames frames, or empty.
  std::string keys;                      ///< Scripted key presses, one per frame.
  bool play = false;                     ///< Play the file's animation from the first frame.
  std::string animation = "0";           ///< The file's animation K, [ and ] play: its name or index.
  int packet = igi::native_packet_width;  ///< Packet width at the start: one native register, as igi-render's.
  int frames = 0;                        ///< Frames before quitting (0: until closed).
  igi::RenderSettings settings;          ///< The IGI settings at the start.
  std::optional<int> temporal;           ///< --temporal as given; unset: default_temporal_frames.
};

/// Index of the first element of `range` equal to `value` under `same`, or -1.
template <class Range, class Value, class Same>
int index_of(const Range& range, const Value& value, Same same) {
  int i = 0;
  for (const auto& element : range) {
    if (same(element, value)) return i;
    ++i;
  }
  return -1;
}

/// The help text of the keys, printed at start and on H.
constexpr const char* key_help =
    "igi-view keys: mouse drag orbit, wheel zoom, W/A/S/D fly, Q/E down/up, arrows + PageUp/PageDown move the light,\n"
    "  L animate the light, +/- VPLs per pixel, F filter, I interleaving size, N anti-aliasing, B backend/packet,\n"
    "  T temporal reuse on/off, K play/pause the file's animation, [ ] step it back/forward, P screenshot,\n"
    "  R reset view, H help, Esc quit\n";

/// The SDL window, its renderer and streaming texture; released in reverse order.
class Window {
 public:
  /// Opens a window of width x height pixels titled `title`; throws std::runtime_error naming SDL's error.
  Window(int width, int height, const std::string& title) {
    // SIGINT and SIGTERM are igi's (common/stop_signals.hpp): SDL would turn them into a quit
    // event that a window busy rendering never reads.
    SDL_SetHint(SDL_HINT_NO_SIGNAL_HANDLERS, "1");
    if (SDL_Init(SDL_INIT_VIDEO) != 0) throw std::runtime_error(std::string("SDL_Init: ") + SDL_GetError());
    window_ = SDL_CreateWindow(title.c_str(), SDL_WINDOWPOS_UNDEFINED, SDL_WINDOWPOS_UNDEFINED, width, height,
                               SDL_WINDOW_RESIZABLE);
    if (!window_) throw std::runtime_error(std::string("SDL_CreateWindow: ") + SDL_GetError());
    renderer_ = SDL_CreateRenderer(window_, -1, 0);
    if (!renderer_) throw std::runtime_error(std::string("SDL_CreateRenderer: ") + SDL_GetError());
    texture_ = SDL_CreateTexture(renderer_, SDL_PIXELFORMAT_RGB24, SDL_TEXTUREACCESS_STREAMING, width, height);
    if (!texture_) throw std::runtime_error(std::string("SDL_CreateTexture: ") + SDL_GetError());
  }
  ~Window() {
    if (texture_) SDL_DestroyTexture(texture_);
    if (renderer_) SDL_DestroyRenderer(renderer_);
    if (window_) SDL_DestroyWindow(window_);
    SDL_Quit();
  }
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  /// Shows `image` scaled to the window; with `capture`, also returns the window's pixels as shown.
  std::optional<igi::Rgb8Image> show(const igi::Rgb8Image& image, bool capture) {
    if (SDL_UpdateTexture(texture_, nullptr, image.bytes.data(), image.width * 3) != 0)
      throw std::runtime_error(std::string("SDL_UpdateTexture: ") + SDL_GetError());
    SDL_RenderClear(renderer_);
    SDL_RenderCopy(renderer_, texture_, nullptr, nullptr);
    std::optional<igi::Rgb8Image> shown;
    if (capture) {
      int width = 0, height = 0;
      if (SDL_GetRendererOutputSize(renderer_, &width, &height) != 0)
        throw std::runtime_error(std::string("SDL_GetRendererOutputSize: ") + SDL_GetError());
      shown = igi::Rgb8Image(width, height);
      if (SDL_RenderReadPixels(renderer_, nullptr, SDL_PIXELFORMAT_RGB24, shown->bytes.data(), width * 3) != 0)
        throw std::runtime_error(std::string("SDL_RenderReadPixels: ") + SDL_GetError());
    }
    SDL_RenderPresent(renderer_);
    return shown;
  }
  /// Sets the title bar.
  void set_title(const std::string& title) { SDL_SetWindowTitle(window_, title.c_str()); }

 private:
  SDL_Window* window_ = nullptr;
  SDL_Renderer* renderer_ = nullptr;
  SDL_Texture* texture_ = nullptr;
};

/// The viewer's state and loop.
class Viewer {
 public:
  /// A viewer of `scene` with `options`.
  Viewer(igi::Scene& scene, const Options& options)
      : scene_(scene),
        options_(options),
        settings_(options.settings),
        filter_(index_of(filter_choices, options.filter, [](const char* a, const std::string& b) { return b == a; })),
        backend_(index_of(backend_choices, options, [](const igi::programs::BackendChoice& c, const Options& o) {
          return o.backend == c.backend && (o.backend != "embree" || o.packet == c.packet);
        })),
        light_(igi_view::find_movable_light(scene)),
        start_camera_(scene.cameras.empty() ? igi::default_camera(scene) : scene.cameras.front()),
        camera_(start_camera_, target_distance()),
        window_(options.settings.width, options.settings.height, "igi-view") {
    const igi::Bounds bounds = scene.bounds();
    diagonal_ = bounds.empty() ? 1.0f : glm::length(bounds.extent());
    orbit_radius_ = igi_view::light_orbit_radius(bounds);
    if (filter_ < 0) throw UsageError("--filter: unknown filter '" + options.filter + "'");
    if (backend_ < 0)
      throw UsageError("--backend/--packet: " + options.backend + "/" + std::to_string(options.packet) +
                       " is not one of " + igi::programs::describe_backends(ViewBackends{}));
    const igi::Animation animation = igi::parse_animation(options.animate);
    animate_light_ = animation == igi::Animation::light;
    animate_camera_ = animation == igi::Animation::camera;
    if (animate_light_ && !light_) throw UsageError("--animate light: the scene has no light that can move");
    if (options.settings.temporal_frames > 0) temporal_frames_when_on_ = options.settings.temporal_frames;
    if (!scene.animations.empty()) {
      try {
        player_.emplace(scene, igi::find_animation(scene, options.animation), true);
      } catch (const igi::SceneError& e) {
        throw UsageError(std::string("--animation: ") + e.what());
      }
    } else if (options.play) {
      throw UsageError("--play: scene '" + scene.name + "' has no animation");
    }
    playing_ = options.play;
    rebuild();
  }

  /// Runs until the window closes, Esc, or `--frames` frames; returns the exit code.
  int run() {
    std::fputs(key_help, stdout);
    std::vector<double> milliseconds;
    for (std::uint32_t frame = 0;; ++frame) {
      if (igi::programs::stop_requested()) return igi::programs::stopped("igi-view");
      if (frame < options_.keys.size()) press(options_.keys[frame]);
      if (!handle_events()) break;
      animate();
      const igi::Frame rendered = renderer_->render(camera_.camera(), frame);
      if (igi::programs::stop_requested()) return igi::programs::stopped("igi-view");
      milliseconds.push_back(rendered.statistics.milliseconds);
      // Temporal reuse averages inside the renderer (and keeps its history while the camera
      // moves); without it, a still view accumulates here and restarts on any change.
      if (settings_.temporal_frames > 0) accumulator_.reset();
      accumulator_.add(rendered.hdr);
      const igi::Rgb8Image shown = igi_view::tone_map(accumulator_.mean());
      const bool last = options_.frames > 0 && int(frame) + 1 >= options_.frames;
      const bool capture = screenshot_requested_ || (last && !options_.screenshot.empty());
      const std::optional<igi::Rgb8Image> captured = window_.show(shown, capture);
      if (captured) {
        const std::string path =
            last && !options_.screenshot.empty() ? options_.screenshot : screenshot_names_(int(frame)).string();
        igi::write_image(path, *captured);
        std::printf("wrote %s\n", path.c_str());
        screenshot_requested_ = false;
      }
      window_.set_title(title(rendered));
      if (last) break;
    }
    if (!milliseconds.empty()) {
      const double median = igi::programs::median(milliseconds);
      std::printf("%zu frames, median %.2f ms (%.1f fps), last image accumulated over %d frames\n",
                  milliseconds.size(), median, median > 0.0 ? 1000.0 / median : 0.0, accumulated_frames());
    }
    return 0;
  }

 private:
  /// Distance from the start camera to the scene's centre: what the mouse orbits around.
  float target_distance() const {
    const igi::Bounds bounds = scene_.bounds();
    const float distance = glm::length(bounds.center() - start_camera_.position());
    // A camera sitting at the centre orbits a point a tenth of the scene's size ahead (plus 1 mm,
    // so a scene of one point still gets a positive distance).
    return distance > 0.0f ? distance : 0.1f * glm::length(bounds.extent()) + 1e-3f;
  }

  /// Builds the renderer for the current settings (backend BVHs are rebuilt from the scene as it is now).
  void rebuild() {
    igi::validate(settings_);
    renderer_.reset();
    renderer_ = make_renderer(backend_choices[backend_], scene_, settings_, filter_choices[filter_], options_.vpl_sampler);
    std::printf("renderer: %s/%d M=%d S=%d N=%d %s temporal %d\n", backend_choices[backend_].backend,
                backend_choices[backend_].packet, settings_.vpls_per_pixel, settings_.interleave, settings_.antialiasing,
                filter_choices[filter_], settings_.temporal_frames);
    std::fflush(stdout);
    restart();
  }
  /// Queues a key press of `key` (a lower-case letter, '+' or '-', whose SDL key codes are their ASCII codes).
  static void press(char key) {
    SDL_Event event{};
    event.type = SDL_KEYDOWN;
    event.key.state = SDL_PRESSED;
    event.key.keysym.sym = SDL_Keycode(key);
    if (SDL_PushEvent(&event) < 0) throw std::runtime_error(std::string("SDL_PushEvent: ") + SDL_GetError());
  }
  /// Something changed: the accumulated frames no longer describe the view.
  void restart() noexcept { accumulator_.reset(); }

  /// Moves the light to its loaded placement plus `light_offset_`.
  void place_light() {
    if (!light_) return;
    if (light_->kind == igi_view::MovableLight::Kind::punctual)
      renderer_->set_light(light_->index, light_->moved_light(light_offset_));
    else
      renderer_->set_instance_transform(light_->index, light_->moved_transform(light_offset_));
    restart();
  }

  /// One step of the scripted or key-toggled animation.
  void animate() {
    if (animate_light_ && light_) {
      light_offset_ = igi_view::light_orbit_offset(animation_frame_++, orbit_radius_, animation_period);
      place_light();
    }
    if (animate_camera_) {
      camera_.orbit(glm::two_pi<float>() / float(animation_period), 0.0f);
      restart();
    }
    if (playing_) seek(play_time_ + play_step);
  }

  /// Poses the scene at `seconds` into the file's animation (looping), if it has one.
  void seek(double seconds) {
    if (!player_) return;
    play_time_ = seconds;
    renderer_->apply((*player_)(play_time_, camera_.camera()));
    restart();
  }

  /// Handles pending events; false when the viewer should quit.
  bool handle_events() {
    SDL_Event event;
    // Fly and light steps per frame or key press: 1% of the scene's diagonal.
    const float step = 0.01f * diagonal_;
    while (SDL_PollEvent(&event)) {
      switch (event.type) {
        case SDL_QUIT: return false;
        case SDL_MOUSEMOTION:
          if (event.motion.state & SDL_BUTTON_LMASK) {
            // 0.005 rad per pixel: dragging across a 640-pixel window turns about half a circle.
            camera_.orbit(0.005f * float(event.motion.xrel), -0.005f * float(event.motion.yrel));
            restart();
          }
          break;
        case SDL_MOUSEWHEEL:
          // 10% closer or farther per wheel notch.
          camera_.zoom(event.wheel.y > 0 ? 0.9f : 1.0f / 0.9f);
          restart();
          break;
        case SDL_KEYDOWN:
          if (!key(event.key.keysym.sym, step)) return false;
          break;
        default: break;
      }
    }
    const Uint8* keys = SDL_GetKeyboardState(nullptr);
    const float along = float(keys[SDL_SCANCODE_W]) - float(keys[SDL_SCANCODE_S]);
    const float side = float(keys[SDL_SCANCODE_D]) - float(keys[SDL_SCANCODE_A]);
    const float up = float(keys[SDL_SCANCODE_E]) - float(keys[SDL_SCANCODE_Q]);
    if (along != 0.0f || side != 0.0f || up != 0.0f) {
      camera_.fly(along * step, side * step, up * step);
      restart();
    }
    return true;
  }

  /// Handles one key press; false to quit.
  bool key(SDL_Keycode code, float step) {
    glm::vec3 light_move(0.0f);
    switch (code) {
      case SDLK_ESCAPE: return false;
      case SDLK_h: std::fputs(key_help, stdout); break;
      case SDLK_p: screenshot_requested_ = true; break;
      case SDLK_r:
        camera_ = igi_view::OrbitCamera(start_camera_, target_distance());
        restart();
        break;
      case SDLK_l: animate_light_ = !animate_light_ && light_.has_value(); break;
      case SDLK_k: playing_ = !playing_ && player_.has_value(); break;
      case SDLK_LEFTBRACKET: seek(play_time_ - scrub_step); break;
      case SDLK_RIGHTBRACKET: seek(play_time_ + scrub_step); break;
      case SDLK_PLUS: case SDLK_EQUALS: case SDLK_KP_PLUS:
        settings_.vpls_per_pixel = std::min(settings_.vpls_per_pixel * 2, igi::max_vpls_per_pixel);
        rebuild();
        break;
      case SDLK_MINUS: case SDLK_KP_MINUS:
        settings_.vpls_per_pixel = std::max(settings_.vpls_per_pixel / 2, settings_.antialiasing);
        rebuild();
        break;
      case SDLK_f:
        filter_ = (filter_ + 1) % int(std::size(filter_choices));
        rebuild();
        break;
      case SDLK_i:
        // Interleaving sizes 1 (none) to 5: beyond 5 x 5 the filter window blurs small objects.
        settings_.interleave = settings_.interleave % 5 + 1;
        rebuild();
        break;
      case SDLK_n: {
        const int i = index_of(antialiasing_choices, settings_.antialiasing, [](int a, int b) { return a == b; });
        settings_.antialiasing = antialiasing_choices[(i + 1) % int(std::size(antialiasing_choices))];
        settings_.vpls_per_pixel = std::max(settings_.vpls_per_pixel, settings_.antialiasing);
        rebuild();
        break;
      }
      case SDLK_b:
        backend_ = (backend_ + 1) % int(std::size(backend_choices));
        rebuild();
        break;
      case SDLK_t:
        settings_.temporal_frames = settings_.temporal_frames > 0 ? 0 : temporal_frames_when_on_;
        rebuild();
        break;
      case SDLK_LEFT: light_move.x -= step; break;
      case SDLK_RIGHT: light_move.x += step; break;
      case SDLK_UP: light_move.z -= step; break;
      case SDLK_DOWN: light_move.z += step; break;
      case SDLK_PAGEUP: light_move.y += step; break;
      case SDLK_PAGEDOWN: light_move.y -= step; break;
      default: break;
    }
    if (light_move != glm::vec3(0.0f) && light_) {
      light_offset_ += light_move;
      place_light();
    }
    return true;
  }

  /// Frames the shown image averages: with temporal reuse the renderer's still frames (its
  /// history caps them at --temporal), else the viewer's own accumulator's.
  int accumulated_frames() const {
    return settings_.temporal_frames > 0 ? std::min(renderer_->still_frames() + 1, settings_.temporal_frames)
                                         : accumulator_.count();
  }

  /// The title bar: timings, settings and how many frames the image holds.
  std::string title(const igi::Frame& frame) const {
    const double ms = frame.statistics.milliseconds;
    const int frames = accumulated_frames();
    char text[256];
    std::snprintf(text, sizeof text, "igi-view  %.1f ms  %.1f fps  %.2f Mrays/s  |  %s/%d  M=%d  S=%d  N=%d  %s  |  %s%d frame%s",
                  ms, ms > 0.0 ? 1000.0 / ms : 0.0, frame.statistics.mrays_per_second(), backend_choices[backend_].backend,
                  backend_choices[backend_].packet, settings_.vpls_per_pixel, settings_.interleave,
                  settings_.antialiasing, filter_choices[filter_], settings_.temporal_frames > 0 ? "temporal " : "",
                  frames, frames == 1 ? "" : "s");
    return text;
  }

  igi::Scene& scene_;
  Options options_;
  /// Names of the P key's screenshots, numbered by frame as igi-render numbers an animation's images.
  igi::programs::FrameNames screenshot_names_{"igi-view.png", 1};
  igi::RenderSettings settings_;
  int filter_;
  int backend_;
  std::optional<igi_view::MovableLight> light_;
  igi::Camera start_camera_;
  igi_view::OrbitCamera camera_;
  Window window_;
  std::unique_ptr<ViewRenderer> renderer_;
  igi_view::ProgressiveAccumulator accumulator_;
  glm::vec3 light_offset_{0.0f};
  float diagonal_ = 1.0f;
  float orbit_radius_ = 0.0f;
  std::uint32_t animation_frame_ = 0;
  bool animate_light_ = false;
  bool animate_camera_ = false;
  bool screenshot_requested_ = false;
  std::optional<igi::AnimationPlayer> player_;  ///< The file's animation (none without one).
  bool playing_ = false;                        ///< Whether it advances by play_step each frame.
  double play_time_ = 0.0;                      ///< Seconds into it the scene is posed at.
  /// History length the T key switches temporal reuse on with: --temporal's, else the programs' default.
  int temporal_frames_when_on_ = igi::programs::default_temporal_frames;
};

}  // namespace

int main(int argc, char** argv) {
  igi::programs::install_stop_signals();
  Options options;
  igi::programs::CommandLine command_line{"igi-view", "interactive global illumination in a window"};
  igi::programs::add_scene_options(command_line, options);
  igi::programs::add_size_option(command_line, options.size);
  igi::programs::add_sampling_options(command_line, options.settings);
  igi::programs::add_filter_options(command_line, options.filter, options.settings);
  igi::programs::add_vpl_sampler_option(command_line, options.vpl_sampler);
  igi::programs::add_backend_options(command_line, options.backend, options.packet);
  igi::programs::add_threads_option(command_line, options.settings.threads, "worker threads (0: all cores)");
  igi::programs::add_seed_option(command_line, options.settings.seed);
  igi::programs::add_temporal_option(command_line, options.temporal, options.settings,
                                     "By default " + std::to_string(igi::programs::default_temporal_frames) +
                                         " frames (the T key switches it off and on)");
  command_line.add("--frames", options.frames, "quit after this many frames (0: run until closed)").range(0, 1000000).show_default();
  igi::programs::add_animate_option(command_line, options.animate,
                                    "what moves from the first frame: light: the light circles, camera: the view orbits the scene",
                                    {"none", "light", "camera"});
  command_line.add("--keys", options.keys, "key presses, one per frame from the first (any of bfiklnprt+-[]), to script a session");
  command_line.flag("--play", options.play, "play the file's own animation from the first frame (K pauses it)");
  command_line.add("--animation", options.animation, "the file's animation to play: its name or index").show_default();
  command_line.add("--screenshot", options.screenshot, "PNG of the window after the last of --frames frames (interactively: P key)");
  if (const std::optional<int> exit_code = command_line.parse(argc, argv)) return *exit_code;
  try {
    const igi::programs::ImageSize size = igi::programs::parse_image_size(options.size);
    options.settings.width = size.width;
    options.settings.height = size.height;
    options.settings.temporal_frames = options.temporal.value_or(igi::programs::default_temporal_frames);
    igi::programs::check_scene_options(options);
    // The reference and saarcor backends come in one packet width each here.
    if (options.backend == "reference") options.packet = 8;
    if (options.backend == "saarcor") options.packet = 64;
    if (!options.screenshot.empty() && igi::image_format(options.screenshot) != igi::ImageFormat::png)
      throw UsageError("--screenshot: '" + options.screenshot + "' must end in .png");
    if (options.keys.find_first_not_of("bfiklnprt+-[]") != std::string::npos)
      throw UsageError("--keys: '" + options.keys + "' has a key other than b f i k l n p r t + - [ ]");
    if (!options.screenshot.empty() && options.frames == 0)
      throw UsageError("--screenshot needs --frames N (interactively, press P)");
    igi::validate(options.settings);
  } catch (const std::exception& e) {
    std::cerr << "igi-view: " << e.what() << "\n";
    return 2;
  }
  try {
    igi::Scene scene = igi::programs::load_scene(options);
    Viewer viewer(scene, options);
    return viewer.run();
  } catch (const UsageError& e) {
    std::cerr << "igi-view: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "igi-view: " << e.what() << "\n";
    return 1;
  }
}
