#pragma once
// The statistics a program prints with --stats json: one JSON object on one line of stdout.
// nlohmann-json stays behind this class, compiled once in stats_json.cpp (igi_command_line).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace igi::programs {

/// One JSON object of named statistics; setting a name again replaces its value.
class StatsJson {
 public:
  /// An empty object.
  StatsJson();
  ~StatsJson();
  /// A copy of `other`'s fields.
  StatsJson(const StatsJson& other);
  /// Takes `other`'s fields.
  StatsJson(StatsJson&& other);
  /// Replaces the fields with a copy of `other`'s.
  StatsJson& operator=(const StatsJson& other);
  /// Replaces the fields with `other`'s.
  StatsJson& operator=(StatsJson&& other) noexcept;

  /// Sets the field `name` to a whole number.
  StatsJson& set(const std::string& name, int value);
  /// Sets the field `name` to a whole number.
  StatsJson& set(const std::string& name, unsigned value);
  /// Sets the field `name` to a whole number.
  StatsJson& set(const std::string& name, std::int64_t value);
  /// Sets the field `name` to a whole number (a count, a size).
  StatsJson& set(const std::string& name, std::uint64_t value);
  /// Sets the field `name` to a number.
  StatsJson& set(const std::string& name, double value);
  /// Sets the field `name` to true or false.
  StatsJson& set(const std::string& name, bool value);
  /// Sets the field `name` to a string.
  StatsJson& set(const std::string& name, const std::string& value);
  /// Sets the field `name` to a string.
  StatsJson& set(const std::string& name, const char* value);
  /// Sets the field `name` to null (a statistic not measured in this run).
  StatsJson& set(const std::string& name, std::nullptr_t);
  /// Sets the field `name` to an object.
  StatsJson& set(const std::string& name, const StatsJson& value);
  /// Sets the field `name` to an array of whole numbers.
  StatsJson& set(const std::string& name, const std::vector<int>& values);
  /// Sets the field `name` to an array of objects.
  StatsJson& set(const std::string& name, const std::vector<StatsJson>& values);
  /// Sets every field of `other` here.
  StatsJson& update(const StatsJson& other);

  /// The object as JSON text on one line, fields in name order.
  std::string dump() const;
  /// Writes dump() and a newline to stdout, and flushes it.
  void print() const;

 private:
  struct Fields;                    ///< The nlohmann::json object.
  std::unique_ptr<Fields> fields_;  ///< Never null.
};

}  // namespace igi::programs
