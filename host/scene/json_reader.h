// host/scene/json_reader.h: typed, range-checked reads of JSON fields that name the file and the
// JSON path of the field in every error (`scenes/a.json: bodies[3].mass: ...`).
#pragma once

#include <cstdint>
#include <initializer_list>
#include <span>
#include <string>
#include <string_view>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "host/core/option_table.h"
#include "host/core/limits.h"
#include "rubble/error.h"
#include "rubble/scene.h"

namespace rubble {

using Json = nlohmann::json;

/// Parses JSON text. Malformed text is BadInput at `file` with the line and column; a key that
/// appears twice in one object is BadInput at its path (the JSON library would keep only one);
/// arrays and objects nested more than kMaxJsonDepth deep are BadInput at the path where the
/// nesting passes the limit.
Result<Json> parseJsonText(std::string_view text, const std::string& file);

/// What a number field may hold. Every range also refuses a number that is not zero but too
/// small for single precision (it would read as 0 or lose its digits: below 1.2e-38).
enum class Range {
    Finite,       ///< any finite number
    Positive,     ///< > 0
    NonNegative,  ///< >= 0
    UnitInterval, ///< 0..1
    Length,       ///< kMinLength..kMaxLength, m
};

/// One JSON object of a scene, with its path; reads fields of it with checks.
class ObjectReader {
  public:
    ObjectReader(const Json& json, std::string path, const std::string& file);

    /// BadInput unless the value is an object.
    Status checkIsObject() const;
    /// BadInput for the first key not in `allowed` (unknown keys are usually typos).
    Status checkKeys(std::initializer_list<std::string_view> allowed) const;
    Status checkKeys(std::span<const std::string_view> allowed) const;

    bool has(std::string_view key) const;
    const Json& at(std::string_view key) const;
    /// `file: path.key`, for errors about a field.
    std::string where(std::string_view key) const;
    /// `file: path`, for errors about the object itself.
    std::string where() const;
    /// `path.key`, the JSON path of a field.
    std::string pathOf(std::string_view key) const;
    const std::string& file() const { return file_; }

    /// BadInput unless the key is present.
    Status require(std::string_view key) const;

    // Each read leaves `out` untouched when the key is absent (its default stands) and fails
    // with BadInput naming the field when the value has the wrong type or range.
    Status read(std::string_view key, float& out, Range range = Range::Finite) const;
    Status read(std::string_view key, std::int64_t& out, std::int64_t min,
                std::int64_t max) const;
    Status read(std::string_view key, bool& out) const;
    Status read(std::string_view key, std::string& out) const;
    Status read(std::string_view key, glm::vec3& out, Range range = Range::Finite) const;
    /// A quaternion written [w, x, y, z]; normalised; BadInput when its norm is near zero.
    Status readQuaternion(std::string_view key, glm::quat& out) const;
    /// A direction; normalised; BadInput when its length is near zero.
    Status readDirection(std::string_view key, glm::vec3& out) const;
    /// An option of the table (host/core/option_table.h), checked and stored by it; BadInput
    /// for a value of the wrong JSON type, or out of the option's range.
    Status readOption(std::string_view key, const Option& option, OptionTarget target) const;

    /// BadInput at `key` with the given message.
    Error fail(std::string_view key, std::string message) const;

  private:
    const Json& json_;
    std::string path_;
    const std::string& file_;
};

/// A value [x, y, z] of finite numbers in `range`; BadInput at `where` otherwise.
Result<glm::vec3> vec3FromJson(const Json& value, const std::string& where,
                               Range range = Range::Finite);

/// A length as a message writes it (%g: 0.0001, 100000).
std::string lengthText(double metres);

/// "[i]", the JSON path suffix of an array element.
std::string indexPath(std::size_t i);

/// The JSON value, shortened to 40 characters for a message; only what is shown is visited.
std::string brief(const Json& value);

} // namespace rubble
