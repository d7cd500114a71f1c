// The Python module igi (its compiled part, igi._igi): bindings only. Scenes are read and lit,
// options parsed and checked, cameras chosen and frames rendered by igi-render's own code
// (examples/common/), so a Renderer built with igi-render's options as keyword arguments renders
// igi-render's images.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "common/command_line.hpp"
#include "common/igi_render_options.hpp"
#include "igi/backends/embree/embree_scene.hpp"
#include "igi/io/image_files.hpp"
#include "igi/io/metrics.hpp"
#include "igi/render/animation.hpp"
#include "igi/scene/animation_sampling.hpp"
#include "igi/scene/camera.hpp"
#include "renderers.hpp"

namespace py = pybind11;

namespace igi::python {
namespace {

using programs::IgiRenderOptions;
using programs::UsageError;

static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "images of glm::vec3 are handed to numpy as float triples");

/// A scene as Python holds it: shared by the Scene objects and Renderers that refer to it.
struct SceneHandle {
  std::shared_ptr<Scene> scene;  ///< Never null.
};

/// Three numbers from a Python sequence; TypeError naming `what` otherwise.
glm::vec3 vec3_from(const py::handle& value, const char* what) {
  const auto numbers = py::cast<std::vector<float>>(value);
  if (numbers.size() != 3) throw py::type_error(std::string(what) + " must be 3 numbers");
  return {numbers[0], numbers[1], numbers[2]};
}

/// A Python tuple of the three components.
py::tuple tuple_of(const glm::vec3& v) { return py::make_tuple(v.x, v.y, v.z); }

/// A 4x4 numpy array (row-major, rows as in mathematics) of a glm matrix (column-major).
py::array_t<float> array_of(const glm::mat4& m) {
  py::array_t<float> out({4, 4});
  auto view = out.mutable_unchecked<2>();
  for (int row = 0; row < 4; ++row)
    for (int column = 0; column < 4; ++column) view(row, column) = m[column][row];
  return out;
}

/// The glm matrix of a 4x4 array-like (rows as in mathematics).
glm::mat4 matrix_from(const py::handle& value) {
  const auto array = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!array || array.ndim() != 2 || array.shape(0) != 4 || array.shape(1) != 4)
    throw py::type_error("a transform must be a 4x4 matrix");
  const auto view = array.unchecked<2>();
  glm::mat4 m(1.0f);
  for (int row = 0; row < 4; ++row)
    for (int column = 0; column < 4; ++column) m[column][row] = view(row, column);
  return m;
}

/// A numpy float32 array of shape (height, width[, channels]) over `data`, owned by `owner` (no copy).
py::array float_image(const py::object& owner, const float* data, int width, int height, int channels) {
  std::vector<py::ssize_t> shape{height, width};
  if (channels > 1) shape.push_back(channels);
  return py::array_t<float>(shape, data, owner);
}

/// The image of a float array of shape (height, width, 3) (copied); ValueError for another shape.
Image image_from(const py::handle& value, const char* what) {
  const auto array = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!array || array.ndim() != 3 || array.shape(2) != 3 || array.shape(0) < 1 || array.shape(1) < 1)
    throw py::value_error(std::string(what) + " must be an array of shape (height, width, 3)");
  Image image(int(array.shape(1)), int(array.shape(0)));
  std::memcpy(image.pixels.data(), array.data(), image.pixels.size() * sizeof(glm::vec3));
  return image;
}

/// The index of the element of `items` that `key` names: an index (negative from the end, as
/// Python's) or an element's name; IndexError or KeyError naming `what` otherwise.
template <class Item>
int index_of(const std::vector<Item>& items, const py::handle& key, const char* what) {
  if (py::isinstance<py::str>(key)) {
    const auto name = key.cast<std::string>();
    for (std::size_t i = 0; i < items.size(); ++i)
      if (items[i].name == name) return int(i);
    throw py::key_error(std::string("no ") + what + " named '" + name + "'");
  }
  int index = key.cast<int>();
  if (index < 0) index += int(items.size());
  if (index < 0 || std::size_t(index) >= items.size())
    throw py::index_error(std::string(what) + " " + std::to_string(key.cast<int>()) + " out of range: the scene has " +
                          std::to_string(items.size()));
  return index;
}

/// Names of the built-in scenes, as igi-render's --builtin takes them.
const std::set<std::string>& builtin_names() {
  static const std::set<std::string> names{"cornell", "window", "blinds", "window-sky", "blinds-sky", "two-windows"};
  return names;
}

/// igi-render's options that a Renderer does not take, and what to do instead.
std::optional<std::string> instead_of(const std::string& keyword) {
  if (keyword == "builtin") return "pass igi.builtin(name) as the scene";
  if (keyword == "output") return "write the frame with frame.write(path)";
  if (keyword == "stats") return "frame.statistics always holds igi-render's --stats json";
  return std::nullopt;
}

/// igi-render's options from a Renderer's keyword arguments: each keyword is igi-render's long
/// option without its dashes, '-' written '_' (vpls=16 is --vpls 16); width and height make
/// --size; a flag takes True or False. Parsed and checked by igi-render's own table and checks.
IgiRenderOptions options_from(const py::kwargs& keywords) {
  IgiRenderOptions options;
  programs::CommandLine command_line("igi.Renderer", "igi-render's options as keyword arguments");
  programs::add_igi_render_options(command_line, options);
  const std::vector<programs::CommandLine::OptionName> names = command_line.option_names();
  std::vector<std::string> arguments;
  std::optional<int> width, height;
  for (const auto& [key, value] : keywords) {
    const auto keyword = key.cast<std::string>();
    if (keyword == "width" || keyword == "height") {
      if (py::isinstance<py::bool_>(value) || !py::isinstance<py::int_>(value))
        throw py::type_error(keyword + " must be a whole number");
      (keyword == "width" ? width : height) = value.cast<int>();
      continue;
    }
    std::string option = "--" + keyword;
    std::replace(option.begin() + 2, option.end(), '_', '-');
    const auto known = std::find_if(names.begin(), names.end(), [&](const auto& name) { return name.name == option; });
    if (known == names.end() || keyword.find('-') != std::string::npos)
      throw py::type_error("Renderer() got an unexpected keyword argument '" + keyword + "' (igi-render has no option " + option + ")");
    if (const std::optional<std::string> instead = instead_of(keyword)) throw py::type_error(keyword + ": " + *instead);
    if (known->flag) {
      if (!py::isinstance<py::bool_>(value)) throw py::type_error(keyword + " is a flag: True or False");
      if (value.cast<bool>()) arguments.push_back(option);
      continue;
    }
    if (py::isinstance<py::bool_>(value)) throw py::type_error(keyword + " takes a value, not True or False");
    arguments.push_back(option + "=" + py::str(value).cast<std::string>());
  }
  if (width || height) {
    if (keywords.contains("size")) throw py::type_error("give width and height, or size, not both");
    arguments.push_back("--size=" + std::to_string(width.value_or(640)) + "x" + std::to_string(height.value_or(480)));
  }
  command_line.parse_arguments(arguments);
  // A Renderer renders the frames it is asked for, in any order and again (render(frame=i)), so
  // each frame stands by itself unless temporal= asks for a history: the library's default, not
  // igi-render's, whose --frames run renders its frames in order.
  if (!options.temporal) options.temporal = 0;
  options.scene_file = "<igi.Scene>";  // the scene is the Renderer's argument, not a file to read
  programs::check_igi_render_options(options, /*sequences=*/false);
  if (options.integrator == "igi" && options.frames != 1)
    throw UsageError("frames: render(frame=i) renders frame i of the IGI pipeline; call it once per frame (frames counts the path tracer's passes)");
  return options;
}

/// A Renderer: a copy of the scene, lit and posed as igi-render would, and a session rendering it.
class PythonRenderer {
 public:
  PythonRenderer(const SceneHandle& source, const py::kwargs& keywords)
      : options_(options_from(keywords)), scene_(std::make_shared<Scene>(*source.scene)) {
    programs::light_scene(*scene_, options_);
    camera_ = programs::choose_camera(*scene_, options_);
    camera_index_ = programs::chosen_camera_index(*scene_, options_);
    // One time of the file's animation or camera path: the scene is posed before the backend is
    // built, as igi-render does.
    programs::pose_for_play(*scene_, camera_, options_, camera_index_);
    if (!options_.camera_path.empty()) path_.emplace(programs::open_camera_path(options_));
    const Animation animation = parse_animation(options_.animate);
    static_cast<void>(animate(*scene_, camera_, animation, 1));  // can this scene move that way?
    if (animation != Animation::none) {
      initial_ = std::make_unique<Scene>(*scene_);  // animations are functions of the initial scene
      animator_.emplace(*initial_, camera_, animation);
    }
    if (options_.backend == "embree" && options_.packet == native_packet_width)
      session_ = make_embree_session(*scene_, options_);
    else if (options_.backend == "reference" && options_.packet == native_packet_width)
      session_ = make_reference_session(*scene_, options_);
    else
      throw UsageError("backend/packet: " + options_.backend + "/" + std::to_string(options_.packet) + " is not one of embree/" +
                       std::to_string(native_packet_width) + ", reference/" + std::to_string(native_packet_width) +
                       " (the module's; igi-render has every backend and width)");
  }

  /// Renders frame `index` as igi-render renders its frame `index`; `camera` and `time` override
  /// the chosen camera and the file's animation time.
  std::shared_ptr<RenderedFrame> render(std::uint32_t index, const py::object& camera, const py::object& time) {
    Camera view = camera_;
    if (!camera.is_none()) view = py::isinstance<py::str>(camera) ? named_camera(camera.cast<std::string>()) : camera.cast<Camera>();
    std::optional<SceneChanges> changes;
    const double seconds = time.is_none() ? double(index) / options_.fps : time.cast<double>();
    // The file's animation plays at a given time, or with play=True; a camera path alone moves only the view.
    const bool plays_file = !time.is_none() ? !scene_->animations.empty() || !path_ : options_.play;
    if (plays_file)
      changes = player()(seconds, view, camera.is_none() ? camera_index_ : -1);
    else if (animator_)
      changes = (*animator_)(index);
    if (path_ && camera.is_none() && (!time.is_none() || options_.plays_sequence())) {
      if (!changes) changes.emplace();
      changes->camera = path_->at(seconds);
    }
    py::gil_scoped_release release;  // rendering runs on igi's own threads
    const std::lock_guard lock(busy_);
    if (changes) {
      session_->apply(*changes);
      if (camera.is_none() || animator_) view = changes->camera;
    }
    return std::make_shared<RenderedFrame>(session_->render(view, index));
  }

  /// Moves instance `instance` (index or name) to `transform` from the next frame on.
  void set_instance_transform(const py::handle& instance, const py::handle& transform) {
    SceneChanges changes;
    changes.instances.emplace_back(index_of(scene_->instances, instance, "instance"), matrix_from(transform));
    apply(changes);
  }

  /// Replaces punctual light `light` (index or name) from the next frame on.
  void set_light(const py::handle& light, const PunctualLight& value) {
    SceneChanges changes;
    changes.lights.emplace_back(index_of(scene_->lights, light, "light"), value);
    apply(changes);
  }

  /// The camera frames use unless told otherwise.
  const Camera& camera() const noexcept { return camera_; }
  /// The scene being rendered, as it is now.
  SceneHandle scene() const { return {scene_}; }
  /// The width and height of the frames.
  std::pair<int, int> size() const noexcept { return {options_.settings.width, options_.settings.height}; }

 private:
  /// Applies `changes` once no other thread renders with this renderer.
  void apply(const SceneChanges& changes) {
    py::gil_scoped_release release;  // a render in another thread finishes without the GIL
    const std::lock_guard lock(busy_);
    session_->apply(changes);
  }
  /// The file's animation the options name, played on the scene (built when first needed).
  const AnimationPlayer& player() {
    if (!player_) player_.emplace(*scene_, find_animation(*scene_, options_.animation), options_.loop);
    return *player_;
  }
  /// The scene's camera named `name`; KeyError otherwise.
  Camera named_camera(const std::string& name) const {
    const Camera* found = find_camera(*scene_, name);
    if (!found) throw py::key_error("no camera named '" + name + "' in " + scene_->name);
    return *found;
  }

  IgiRenderOptions options_;
  std::shared_ptr<Scene> scene_;
  Camera camera_;
  int camera_index_ = -1;
  std::unique_ptr<Scene> initial_;
  std::optional<Animator> animator_;
  std::optional<AnimationPlayer> player_;
  std::optional<CameraPath> path_;  ///< The camera path frames follow (camera_path=...), if any.
  std::unique_ptr<RenderSession> session_;
  std::mutex busy_;  ///< Held while rendering or changing the scene: Python threads may share a renderer.
};

/// A camera at `origin` looking at `target` with `up` upwards and a vertical field of view of
/// `fov` degrees; ValueError for a degenerate one.
Camera look_at(const py::handle& origin, const py::handle& target, const py::handle& up, float fov) {
  const glm::vec3 eye = vec3_from(origin, "origin"), at = vec3_from(target, "target"), upward = vec3_from(up, "up");
  const glm::vec3 forward = at - eye;
  if (!(glm::length(forward) > 0.0f) || !(glm::length(glm::cross(forward, upward)) > 0.0f))
    throw py::value_error("look_at: origin and target must differ, and up must not be parallel to the view");
  if (!(fov > 0.0f && fov < 180.0f)) throw py::value_error("look_at: fov must lie between 0 and 180 degrees");
  Camera camera;
  camera.name = "look_at";
  camera.camera_to_world = glm::inverse(glm::lookAt(eye, at, upward));
  camera.yfov = glm::radians(fov);
  return camera;
}

/// Reads a scene on igi's side, the GIL released.
SceneHandle read(const programs::SceneOptions& options) {
  py::gil_scoped_release release;
  return {std::make_shared<Scene>(programs::read_scene(options))};
}

}  // namespace
}  // namespace igi::python

PYBIND11_MODULE(_igi, m) {
  using namespace igi;
  using namespace igi::python;
  m.doc() = "igi: interactive global illumination (instant radiosity with SIMD ray packets)";

  static py::exception<std::runtime_error> error(m, "Error", PyExc_RuntimeError);
  static py::exception<SceneError> scene_error(m, "SceneError", error.ptr());
  static py::exception<ImageError> image_error(m, "ImageError", error.ptr());
  py::register_exception_translator([](std::exception_ptr thrown) {
    try {
      if (thrown) std::rethrow_exception(thrown);
    } catch (const SceneError& e) {
      scene_error(e.what());
    } catch (const ImageError& e) {
      image_error(e.what());
    } catch (const UsageError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const EmbreeError& e) {
      error(e.what());
    }
  });
  m.attr("__version__") = IGI_VERSION;
  m.attr("packet_width") = native_packet_width;

  py::class_<Camera>(m, "Camera", "A pinhole camera: glTF's, a scene's fitted view, or igi.look_at's")
      .def_readwrite("name", &Camera::name, "The glTF camera's (or its node's) name")
      .def_property(
          "fov", [](const Camera& c) { return glm::degrees(c.yfov); },
          [](Camera& c, float degrees) {
            if (!(degrees > 0.0f && degrees < 180.0f)) throw py::value_error("fov must lie between 0 and 180 degrees");
            c.yfov = glm::radians(degrees);
          },
          "Vertical field of view, degrees (it spans the image's height)")
      .def_property_readonly("position", [](const Camera& c) { return tuple_of(c.position()); }, "The eye's position")
      .def_property(
          "to_world", [](const Camera& c) { return array_of(c.camera_to_world); },
          [](Camera& c, const py::handle& m) { c.camera_to_world = matrix_from(m); },
          "Camera to world, a 4x4 matrix (it looks down its -Z, +Y up)")
      .def("__repr__", [](const Camera& c) { return "igi.Camera('" + c.name + "', fov=" + std::to_string(glm::degrees(c.yfov)) + ")"; });
  m.def("look_at", &look_at, py::arg("origin"), py::arg("target"), py::arg("up") = py::make_tuple(0.0f, 1.0f, 0.0f),
        py::arg("fov") = 39.3077f, "A camera at origin looking at target, fov the vertical field of view in degrees (Cornell's by default)");

  py::enum_<PunctualKind>(m, "LightKind").value("point", PunctualKind::point).value("spot", PunctualKind::spot)
      .value("directional", PunctualKind::directional);
  py::class_<PunctualLight>(m, "Light", "A point, spot or directional light (KHR_lights_punctual)")
      .def_readwrite("name", &PunctualLight::name)
      .def_readwrite("kind", &PunctualLight::kind)
      .def_property("color", [](const PunctualLight& l) { return tuple_of(l.color); },
                    [](PunctualLight& l, const py::handle& v) { l.color = vec3_from(v, "color"); }, "Linear RGB")
      .def_readwrite("intensity", &PunctualLight::intensity, "Scale of color (W/sr; W/m^2 for a directional light)")
      .def_property("position", [](const PunctualLight& l) { return tuple_of(l.position); },
                    [](PunctualLight& l, const py::handle& v) { l.position = vec3_from(v, "position"); })
      .def_property("direction", [](const PunctualLight& l) { return tuple_of(l.direction); },
                    [](PunctualLight& l, const py::handle& v) { l.direction = glm::normalize(vec3_from(v, "direction")); },
                    "Unit direction it shines to (spot, directional)")
      .def("__repr__", [](const PunctualLight& l) { return "igi.Light('" + l.name + "')"; });

  py::class_<SceneHandle>(m, "Scene", "A scene: a glTF file's or a built-in one")
      .def_property_readonly("name", [](const SceneHandle& s) { return s.scene->name; })
      .def_property_readonly("triangles", [](const SceneHandle& s) { return s.scene->triangle_count(); })
      .def_property_readonly("cameras", [](const SceneHandle& s) { return s.scene->cameras; }, "The file's cameras (copies)")
      .def_property_readonly("lights", [](const SceneHandle& s) { return s.scene->lights; }, "The punctual lights (copies)")
      .def_property_readonly("instances", [](const SceneHandle& s) {
        std::vector<std::string> names;
        for (const Instance& instance : s.scene->instances) names.push_back(instance.name);
        return names;
      }, "The instances' names, by index")
      .def("instance_transform", [](const SceneHandle& s, const py::handle& instance) {
        return array_of(s.scene->instances[std::size_t(index_of(s.scene->instances, instance, "instance"))].transform);
      }, py::arg("instance"), "Object to world of an instance (index or name), a 4x4 matrix")
      .def_property_readonly("animations", [](const SceneHandle& s) {
        std::vector<std::string> names;
        for (const auto& animation : s.scene->animations.animations) names.push_back(animation.name);
        return names;
      }, "The file's animations' names, by index")
      .def("__repr__", [](const SceneHandle& s) { return "igi.Scene('" + s.scene->name + "')"; });

  m.def("load", [](const std::string& path) {
    programs::SceneOptions options;
    options.scene_file = path;
    return read(options);
  }, py::arg("path"), "Loads a glTF 2.0 scene (.gltf or .glb)");
  m.def("builtin", [](const std::string& name) {
    if (!builtin_names().count(name))
      throw py::value_error("no built-in scene '" + name + "': cornell, window, blinds, window-sky, blinds-sky or two-windows");
    programs::SceneOptions options;
    options.builtin = name;
    return read(options);
  }, py::arg("name"), "A built-in scene: cornell, window, blinds, window-sky, blinds-sky or two-windows (igi-render --builtin)");

  py::class_<RenderedFrame, std::shared_ptr<RenderedFrame>>(m, "Frame", "One rendered frame; its arrays share its memory")
      .def_property_readonly("width", [](const RenderedFrame& f) { return f.width; })
      .def_property_readonly("height", [](const RenderedFrame& f) { return f.height; })
      .def_property_readonly("hdr", [](const py::object& self) {
        const auto& f = self.cast<const RenderedFrame&>();
        return float_image(self, &f.hdr.pixels.front().x, f.width, f.height, 3);
      }, "Linear radiance, float32 (height, width, 3)")
      .def_property_readonly("rgb8", [](const py::object& self) {
        const auto& f = self.cast<const RenderedFrame&>();
        return py::array_t<std::uint8_t>({f.height, f.width, 3}, f.rgb8.bytes.data(), self);
      }, "Tone-mapped sRGB, uint8 (height, width, 3)")
      .def_property_readonly("albedo", [](const py::object& self) -> py::object {
        const auto& f = self.cast<const RenderedFrame&>();
        if (f.albedo.empty()) return py::none();
        return float_image(self, &f.albedo.front().x, f.width, f.height, 3);
      }, "Diffuse albedo of the first hit, float32 (height, width, 3)")
      .def_property_readonly("normal", [](const py::object& self) -> py::object {
        const auto& f = self.cast<const RenderedFrame&>();
        if (f.normal.empty()) return py::none();
        return float_image(self, &f.normal.front().x, f.width, f.height, 3);
      }, "Unit shading normal of the first hit (world space; 0 where the ray missed), float32 (height, width, 3)")
      .def_property_readonly("depth", [](const py::object& self) -> py::object {
        const auto& f = self.cast<const RenderedFrame&>();
        if (f.depth.empty()) return py::none();
        return float_image(self, f.depth.data(), f.width, f.height, 1);
      }, "Distance along the primary ray to the first hit (0 where it missed), float32 (height, width)")
      .def_property_readonly("statistics", [](const RenderedFrame& f) {
        return py::module_::import("json").attr("loads")(f.statistics);
      }, "What igi-render --stats json prints, as a dict")
      .def("write", [](const RenderedFrame& f, const std::string& path) {
        py::gil_scoped_release release;
        programs::write_output(path, f.hdr, f.rgb8);
      }, py::arg("path"), "Writes .png (tone mapped), .exr or .pfm (linear radiance)");

  py::class_<PythonRenderer>(m, "Renderer", "Renders a scene with igi-render's options as keyword arguments")
      .def(py::init<const SceneHandle&, const py::kwargs&>(), py::arg("scene"))
      .def("render", &PythonRenderer::render, py::arg("frame") = 0, py::arg("camera") = py::none(), py::arg("time") = py::none(),
           "Renders frame `frame`; camera: an igi.Camera or a camera's name; time: seconds into the file's animation")
      .def("set_instance_transform", &PythonRenderer::set_instance_transform, py::arg("instance"), py::arg("transform"),
           "Moves an instance (index or name) to a 4x4 object-to-world matrix from the next frame on")
      .def("set_light", &PythonRenderer::set_light, py::arg("light"), py::arg("value"),
           "Replaces a punctual light (index or name) from the next frame on")
      .def_property_readonly("camera", &PythonRenderer::camera, "The camera frames use unless told otherwise")
      .def_property_readonly("scene", &PythonRenderer::scene, "The scene being rendered, as it is now")
      .def_property_readonly("size", &PythonRenderer::size, "(width, height)");

  m.def("rmse", [](const py::handle& test, const py::handle& reference) {
    return rmse(image_from(test, "test"), image_from(reference, "reference"));
  }, py::arg("test"), py::arg("reference"), "Root mean squared error over pixels and channels");
  m.def("relmse", [](const py::handle& test, const py::handle& reference, double epsilon, bool ignore_brightest) {
    return relmse(image_from(test, "test"), image_from(reference, "reference"), RelMseOptions{epsilon, ignore_brightest});
  }, py::arg("test"), py::arg("reference"), py::arg("epsilon") = 0.01, py::arg("ignore_brightest") = false,
     "Relative MSE: mean of (test - reference)^2 / (reference^2 + epsilon)");
  m.def("ssim", [](const py::handle& test, const py::handle& reference) {
    return ssim(image_from(test, "test"), image_from(reference, "reference"));
  }, py::arg("test"), py::arg("reference"), "Mean structural similarity of the luminances (1: identical)");
  m.def("write_image", [](const std::string& path, const py::handle& image) {
    const Image hdr = image_from(image, "image");
    py::gil_scoped_release release;
    write_image(path, hdr);
  }, py::arg("path"), py::arg("image"), "Writes a float (height, width, 3) image: .exr, .pfm, or .png (sRGB, clamped)");
  m.def("read_image", [](const std::string& path) {
    auto image = std::make_shared<Image>();
    {
      py::gil_scoped_release release;
      *image = read_image(path);
    }
    py::object owner = py::capsule(new std::shared_ptr<Image>(image), [](void* p) { delete static_cast<std::shared_ptr<Image>*>(p); });
    return float_image(owner, &image->pixels.front().x, image->width, image->height, 3);
  }, py::arg("path"), "Reads .exr, .pfm, .hdr or .png as linear float32 (height, width, 3)");
}
