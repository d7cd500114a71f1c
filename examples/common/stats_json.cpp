// StatsJson over nlohmann-json (see stats_json.hpp).
#include "common/stats_json.hpp"

#include <iostream>

#include <nlohmann/json.hpp>

namespace igi::programs {

struct StatsJson::Fields {
  nlohmann::json object = nlohmann::json::object();  ///< The statistics.
};

StatsJson::StatsJson() : fields_(std::make_unique<Fields>()) {}
StatsJson::~StatsJson() = default;
StatsJson::StatsJson(const StatsJson& other) : fields_(std::make_unique<Fields>(*other.fields_)) {}
StatsJson::StatsJson(StatsJson&& other) : fields_(std::make_unique<Fields>()) { fields_.swap(other.fields_); }
StatsJson& StatsJson::operator=(const StatsJson& other) {
  *fields_ = *other.fields_;
  return *this;
}
StatsJson& StatsJson::operator=(StatsJson&& other) noexcept {
  fields_.swap(other.fields_);
  return *this;
}

StatsJson& StatsJson::set(const std::string& name, int value) {
  fields_->object[name] = value;
  return *this;
}
StatsJson& StatsJson::set(const std::string& name, unsigned value) {
  fields_->object[name] = value;
  return *this;
}
StatsJson& StatsJson::set(const std::string& name, std::int64_t value) {
  fields_->object[name] = value;
  return *this;
}
StatsJson& StatsJson::set(const std::string& name, std::uint64_t value) {
  fields_->object[name] = value;
  return *this;
}
StatsJson& StatsJson::set(const std::string& name, double value) {
  fields_->object[name] = value;
  return *this;
}
StatsJson& StatsJson::set(const std::string& name, bool value) {
  fields_->object[name] = value;
  return *this;
}
StatsJson& StatsJson::set(const std::string& name, const std::string& value) {
  fields_->object[name] = value;
  return *this;
}
StatsJson& StatsJson::set(const std::string& name, const char* value) {
  fields_->object[name] = value;
  return *this;
}
StatsJson& StatsJson::set(const std::string& name, std::nullptr_t) {
  fields_->object[name] = nullptr;
  return *this;
}
StatsJson& StatsJson::set(const std::string& name, const StatsJson& value) {
  fields_->object[name] = value.fields_->object;
  return *this;
}
StatsJson& StatsJson::set(const std::string& name, const std::vector<int>& values) {
  fields_->object[name] = values;
  return *this;
}
StatsJson& StatsJson::set(const std::string& name, const std::vector<StatsJson>& values) {
  nlohmann::json array = nlohmann::json::array();
  for (const StatsJson& value : values) array.push_back(value.fields_->object);
  fields_->object[name] = std::move(array);
  return *this;
}
StatsJson& StatsJson::update(const StatsJson& other) {
  fields_->object.update(other.fields_->object);
  return *this;
}

std::string StatsJson::dump() const { return fields_->object.dump(); }

void StatsJson::print() const { std::cout << dump() << std::endl; }

}  // namespace igi::programs
