// StatsJson over nlohmann-json (see stats_json.hpp).
#include "common/stats_json.hpp"

#include <iostream>
#include <utility>

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

namespace {

/// Sets `object[name]` to `value` and returns `stats`, the StatsJson that holds `object`.
template <class Value>
StatsJson& set_field(StatsJson& stats, nlohmann::json& object, const std::string& name, Value&& value) {
  object[name] = std::forward<Value>(value);
  return stats;
}

}  // namespace

StatsJson& StatsJson::set(const std::string& name, int value) { return set_field(*this, fields_->object, name, value); }
StatsJson& StatsJson::set(const std::string& name, unsigned value) { return set_field(*this, fields_->object, name, value); }
StatsJson& StatsJson::set(const std::string& name, std::int64_t value) { return set_field(*this, fields_->object, name, value); }
StatsJson& StatsJson::set(const std::string& name, std::uint64_t value) { return set_field(*this, fields_->object, name, value); }
StatsJson& StatsJson::set(const std::string& name, double value) { return set_field(*this, fields_->object, name, value); }
StatsJson& StatsJson::set(const std::string& name, bool value) { return set_field(*this, fields_->object, name, value); }
StatsJson& StatsJson::set(const std::string& name, const std::string& value) { return set_field(*this, fields_->object, name, value); }
StatsJson& StatsJson::set(const std::string& name, const char* value) { return set_field(*this, fields_->object, name, value); }
StatsJson& StatsJson::set(const std::string& name, std::nullptr_t) { return set_field(*this, fields_->object, name, nullptr); }
StatsJson& StatsJson::set(const std::string& name, const std::vector<int>& values) { return set_field(*this, fields_->object, name, values); }
StatsJson& StatsJson::set(const std::string& name, const StatsJson& value) {
  return set_field(*this, fields_->object, name, value.fields_->object);
}
StatsJson& StatsJson::set(const std::string& name, const std::vector<StatsJson>& values) {
  nlohmann::json array = nlohmann::json::array();
  for (const StatsJson& value : values) array.push_back(value.fields_->object);
  return set_field(*this, fields_->object, name, std::move(array));
}
StatsJson& StatsJson::update(const StatsJson& other) {
  fields_->object.update(other.fields_->object);
  return *this;
}

std::string StatsJson::dump() const { return fields_->object.dump(); }

void StatsJson::print() const { std::cout << dump() << std::endl; }

}  // namespace igi::programs
