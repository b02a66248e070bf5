#include "sim/embree.hpp"

#include <mutex>
#include <string>
#include <utility>

#include "core/error.hpp"

namespace beadtwin::embree {

struct ErrorSlot {
  std::mutex mutex;
  RTCError code = RTC_ERROR_NONE;
  std::string message;  // the first error since the last check; later ones are usually its consequences
};

namespace {

std::string_view error_name(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE:
      return "no error";
    case RTC_ERROR_UNKNOWN:
      return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT:
      return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION:
      return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY:
      return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU:
      return "unsupported CPU";
    case RTC_ERROR_CANCELLED:
      return "cancelled";
  }
  return "unknown error";
}

void record_error(void* user, RTCError code, const char* message) {
  auto* slot = static_cast<ErrorSlot*>(user);
  const std::lock_guard lock(slot->mutex);
  if (slot->code != RTC_ERROR_NONE) return;
  slot->code = code;
  slot->message = message != nullptr ? message : "";
}

void throw_if_error(ErrorSlot& slot, std::string_view call) {
  RTCError code = RTC_ERROR_NONE;
  std::string message;
  {
    const std::lock_guard lock(slot.mutex);
    code = std::exchange(slot.code, RTC_ERROR_NONE);
    message = std::exchange(slot.message, {});
  }
  if (code == RTC_ERROR_NONE) return;
  throw InternalError("Embree " + std::string(call) + ": " + std::string(error_name(code)) +
                      (message.empty() ? "" : ": " + message));
}

}  // namespace

// --- Device ---

Device::Device(const char* config) : errors_(std::make_shared<ErrorSlot>()) {
  device_ = rtcNewDevice(config);
  // Without a device there is no callback yet: Embree keeps this error for the null device.
  if (device_ == nullptr)
    throw InternalError("Embree rtcNewDevice: " + std::string(error_name(rtcGetDeviceError(nullptr))));
  rtcSetDeviceErrorFunction(device_, &record_error, errors_.get());
}

Device::~Device() {
  if (device_ != nullptr) rtcReleaseDevice(device_);
}

Device::Device(Device&& other) noexcept
    : device_(std::exchange(other.device_, nullptr)), errors_(std::move(other.errors_)) {}

Device& Device::operator=(Device&& other) noexcept {
  if (this != &other) {
    if (device_ != nullptr) rtcReleaseDevice(device_);
    device_ = std::exchange(other.device_, nullptr);
    errors_ = std::move(other.errors_);
  }
  return *this;
}

void Device::check(std::string_view call) const {
  throw_if_error(*errors_, call);
}

// --- Geometry ---

Geometry::Geometry(const Device& device, RTCGeometryType type) : errors_(device.errors()) {
  geometry_ = rtcNewGeometry(device.get(), type);
  throw_if_error(*errors_, "rtcNewGeometry");
  if (geometry_ == nullptr) throw InternalError("Embree rtcNewGeometry returned no geometry");
}

Geometry::~Geometry() {
  if (geometry_ != nullptr) rtcReleaseGeometry(geometry_);
}

Geometry::Geometry(Geometry&& other) noexcept
    : geometry_(std::exchange(other.geometry_, nullptr)), errors_(std::move(other.errors_)) {}

Geometry& Geometry::operator=(Geometry&& other) noexcept {
  if (this != &other) {
    if (geometry_ != nullptr) rtcReleaseGeometry(geometry_);
    geometry_ = std::exchange(other.geometry_, nullptr);
    errors_ = std::move(other.errors_);
  }
  return *this;
}

void* Geometry::new_buffer_bytes(RTCBufferType type, unsigned slot, RTCFormat format, std::size_t stride,
                                 std::size_t count) {
  void* data = rtcSetNewGeometryBuffer(geometry_, type, slot, format, stride, count);
  throw_if_error(*errors_, "rtcSetNewGeometryBuffer");
  if (data == nullptr && count > 0) throw InternalError("Embree rtcSetNewGeometryBuffer returned no buffer");
  return data;
}

void Geometry::commit() {
  rtcCommitGeometry(geometry_);
  throw_if_error(*errors_, "rtcCommitGeometry");
}

// --- Scene ---

Scene::Scene(const Device& device) : errors_(device.errors()) {
  scene_ = rtcNewScene(device.get());
  throw_if_error(*errors_, "rtcNewScene");
  if (scene_ == nullptr) throw InternalError("Embree rtcNewScene returned no scene");
}

Scene::~Scene() {
  if (scene_ != nullptr) rtcReleaseScene(scene_);
}

Scene::Scene(Scene&& other) noexcept
    : scene_(std::exchange(other.scene_, nullptr)), errors_(std::move(other.errors_)) {}

Scene& Scene::operator=(Scene&& other) noexcept {
  if (this != &other) {
    if (scene_ != nullptr) rtcReleaseScene(scene_);
    scene_ = std::exchange(other.scene_, nullptr);
    errors_ = std::move(other.errors_);
  }
  return *this;
}

void Scene::set_flags(RTCSceneFlags flags) {
  rtcSetSceneFlags(scene_, flags);
  throw_if_error(*errors_, "rtcSetSceneFlags");
}

void Scene::set_build_quality(RTCBuildQuality quality) {
  rtcSetSceneBuildQuality(scene_, quality);
  throw_if_error(*errors_, "rtcSetSceneBuildQuality");
}

unsigned Scene::attach(const Geometry& geometry) {
  const unsigned id = rtcAttachGeometry(scene_, geometry.get());
  throw_if_error(*errors_, "rtcAttachGeometry");
  return id;
}

void Scene::commit() {
  rtcCommitScene(scene_);
  throw_if_error(*errors_, "rtcCommitScene");
}

}  // namespace beadtwin::embree
