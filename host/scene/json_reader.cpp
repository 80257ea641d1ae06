// host/scene/json_reader.cpp: checked field reads for the scene loader.
#include "host/scene/json_reader.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>
#include <vector>

namespace rubble {
namespace {

std::string typeName(const Json& v) {
    if (v.is_number_integer()) return "an integer";
    if (v.is_number()) return "a number";
    if (v.is_string()) return "a string";
    if (v.is_boolean()) return "a boolean";
    if (v.is_array()) return "an array";
    if (v.is_object()) return "an object";
    return "null";
}

// Line and column (1-based) of a byte offset in text.
std::pair<int, int> lineColumn(std::string_view text, std::size_t byte) {
    int line = 1, column = 1;
    for (std::size_t i = 0; i < byte && i < text.size(); ++i) {
        if (text[i] == '\n') {
            ++line;
            column = 1;
        } else {
            ++column;
        }
    }
    return {line, column};
}

// Thrown by the reader to stop at a value nested deeper than kMaxJsonDepth, before anything
// that walks the value recursively (the library's dump, its comparisons) meets it.
struct NestedTooDeep {};

// Builds the document from the parser's events (Json::sax_parse) while it tracks the JSON path,
// to find keys given twice and to stop at a value nested deeper than kMaxJsonDepth. Linear in
// the text: Json::parse with a callback (nlohmann/json 3.11) scans the enclosing container for
// a discarded value at the end of every object in it, quadratic in a scene's bodies.
class CheckedJsonReader {
  public:
    explicit CheckedJsonReader(Json& root) : root_(root) {}

    // The parser's events (the SAX interface of nlohmann/json).
    bool null() { return value(nullptr); }
    bool boolean(bool v) { return value(v); }
    bool number_integer(Json::number_integer_t v) { return value(v); }
    bool number_unsigned(Json::number_unsigned_t v) { return value(v); }
    bool number_float(Json::number_float_t v, const Json::string_t&) { return value(v); }
    bool string(Json::string_t& v) { return value(std::move(v)); }
    bool binary(Json::binary_t& v) { return value(Json::binary(std::move(v))); }
    bool start_object(std::size_t) { return open(Json::object(), false); }
    bool start_array(std::size_t) { return open(Json::array(), true); }
    bool key(Json::string_t& k) {
        Frame& f = frames_.back();
        f.key = k;
        // A member is placed once its value is read: the object holds the key already only when
        // it was given before.
        if (f.container->contains(f.key) && duplicatePath_.empty()) duplicatePath_ = path();
        return true;
    }
    bool end_object() { return close(); }
    bool end_array() { return close(); }
    // The parser's own exception (parse_error, or out_of_range for a number beyond a double).
    template <class Exception>
    bool parse_error(std::size_t, const std::string&, const Exception& e) {
        throw e;
    }

    const std::string& duplicatePath() const { return duplicatePath_; }

    // The JSON path the parser is at: the field whose value it is reading; at most `frames`
    // levels of it, then "...".
    std::string path(std::size_t frames = kMaxJsonDepth) const {
        std::string p;
        for (std::size_t k = 0; k < frames_.size(); ++k) {
            const Frame& f = frames_[k];
            if (k == frames) {
                p += "...";
                break;
            }
            if (f.isArray) {
                p += indexPath(f.index);
            } else if (!f.key.empty()) {
                if (!p.empty()) p += ".";
                p += f.key;
            }
        }
        return p;
    }

  private:
    struct Frame {
        Json* container;
        bool isArray;
        std::size_t index;
        std::string key;
    };
    // Puts v where the parser is (the root, the next element, or the member of the last key).
    Json& place(Json&& v) {
        if (frames_.empty()) return root_ = std::move(v);
        Frame& f = frames_.back();
        if (f.isArray) {
            f.container->push_back(std::move(v));
            return f.container->back();
        }
        return (*f.container)[f.key] = std::move(v);
    }
    bool value(Json&& v) {
        place(std::move(v));
        elementDone();
        return true;
    }
    bool open(Json&& container, bool isArray) {
        if (frames_.size() >= kMaxJsonDepth) throw NestedTooDeep{};
        Json& placed = place(std::move(container));
        frames_.push_back(Frame{&placed, isArray, 0, {}});
        return true;
    }
    bool close() {
        frames_.pop_back();
        elementDone();
        return true;
    }
    void elementDone() {
        if (!frames_.empty() && frames_.back().isArray) ++frames_.back().index;
    }
    Json& root_;
    std::vector<Frame> frames_;
    std::string duplicatePath_;
};

} // namespace

std::string lengthText(double metres) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", metres);
    return buf;
}

std::string indexPath(std::size_t i) {
    std::string s(1, '[');
    s += std::to_string(i);
    s += ']';
    return s;
}

namespace {

// Appends the JSON text of a value until `out` holds `limit` characters: each level of nesting
// writes a bracket first, so the recursion is at most `limit` deep, and a large array costs no
// more than its first elements.
void appendBrief(const Json& value, std::string& out, std::size_t limit) {
    if (out.size() >= limit) return;
    if (value.is_array()) {
        out += '[';
        bool first = true;
        for (const Json& element : value) {
            if (out.size() >= limit) return;
            if (!first) out += ',';
            first = false;
            appendBrief(element, out, limit);
        }
        out += ']';
    } else if (value.is_object()) {
        out += '{';
        bool first = true;
        for (const auto& [key, element] : value.items()) {
            if (out.size() >= limit) return;
            if (!first) out += ',';
            first = false;
            out += Json(key).dump();
            out += ':';
            appendBrief(element, out, limit);
        }
        out += '}';
    } else {
        out += value.dump();
    }
}

} // namespace

std::string brief(const Json& value) {
    constexpr std::size_t kShown = 40;
    std::string s;
    appendBrief(value, s, kShown + 1);
    if (s.size() > kShown) s = s.substr(0, kShown - 3) + "...";
    return s;
}

Result<Json> parseJsonText(std::string_view text, const std::string& file) {
    Json json;
    CheckedJsonReader reader(json);
    try {
        Json::sax_parse(text.begin(), text.end(), &reader, Json::input_format_t::json, true, false);
    } catch (const NestedTooDeep&) {
        return makeError(ErrorKind::BadInput, file + ": " + reader.path(4),
                         "the JSON is nested more than " + std::to_string(kMaxJsonDepth) +
                             " levels deep (a scene needs at most 6)");
    } catch (const Json::parse_error& e) {
        const auto [line, column] = lineColumn(text, e.byte > 0 ? e.byte - 1 : 0);
        std::string what = e.what();
        // Keep the library's description of the problem, drop its own prefix and position.
        if (const auto colon = what.find(": "); colon != std::string::npos)
            what = what.substr(colon + 2);
        return makeError(ErrorKind::BadInput, file,
                         "malformed JSON at line " + std::to_string(line) + ", column " +
                             std::to_string(column) + ": " + what);
    } catch (const Json::exception& e) {
        // Out-of-range numbers (1e999) fail inside the parser, at the field being read.
        std::string what = e.what();
        if (const auto bracket = what.find("] "); bracket != std::string::npos)
            what = what.substr(bracket + 2);
        const std::string path = reader.path();
        return makeError(ErrorKind::BadInput, path.empty() ? file : file + ": " + path,
                         "expected a finite number: " + what);
    }
    if (!reader.duplicatePath().empty())
        return makeError(ErrorKind::BadInput, file + ": " + reader.duplicatePath(),
                         "this key is given twice in the same object");
    return json;
}

ObjectReader::ObjectReader(const Json& json, std::string path, const std::string& file)
    : json_(json), path_(std::move(path)), file_(file) {}

Status ObjectReader::checkIsObject() const {
    if (!json_.is_object())
        return makeError(ErrorKind::BadInput, where(),
                         "expected an object, got " + typeName(json_) + " " + brief(json_));
    return {};
}

Status ObjectReader::checkKeys(std::initializer_list<std::string_view> allowed) const {
    return checkKeys(std::span<const std::string_view>(allowed.begin(), allowed.size()));
}

Status ObjectReader::checkKeys(std::span<const std::string_view> allowed) const {
    for (const auto& [key, value] : json_.items()) {
        bool known = false;
        for (std::string_view a : allowed) known = known || a == key;
        if (!known) {
            std::string list;
            for (std::string_view a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
            return makeError(ErrorKind::BadInput, where(key),
                             "unknown key (allowed here: " + list + ")");
        }
    }
    return {};
}

bool ObjectReader::has(std::string_view key) const { return json_.contains(key); }
const Json& ObjectReader::at(std::string_view key) const { return json_.at(std::string(key)); }

std::string ObjectReader::pathOf(std::string_view key) const {
    return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}
std::string ObjectReader::where(std::string_view key) const { return file_ + ": " + pathOf(key); }
std::string ObjectReader::where() const { return path_.empty() ? file_ : file_ + ": " + path_; }

Error ObjectReader::fail(std::string_view key, std::string message) const {
    return makeError(ErrorKind::BadInput, where(key), std::move(message));
}

Status ObjectReader::require(std::string_view key) const {
    if (!has(key)) return fail(key, "is required but missing");
    return {};
}

namespace {

Result<double> numberFromJson(const Json& v, const std::string& where, Range range) {
    auto fail = [&](std::string m) { return makeError(ErrorKind::BadInput, where, std::move(m)); };
    if (!v.is_number()) return fail("expected a number, got " + typeName(v) + " " + brief(v));
    const double out = v.get<double>();
    if (!std::isfinite(out)) return fail("expected a finite number, got " + brief(v));
    if (!std::isfinite(float(out))) return fail("is too large for single precision: " + brief(v));
    // The range holds for the float the value becomes: 1e-300 is not greater than 0.
    const double f = double(float(out));
    const std::string got = ", got " + brief(v) + (f == 0.0 && out != 0.0 ? " (0 as a float)" : "");
    switch (range) {
    case Range::Finite:
        break;
    case Range::Positive:
        if (!(f > 0.0)) return fail("must be greater than 0" + got);
        break;
    case Range::NonNegative:
        if (!(f >= 0.0)) return fail("must be 0 or more" + got);
        break;
    case Range::UnitInterval:
        if (!(f >= 0.0 && f <= 1.0)) return fail("must be between 0 and 1" + got);
        break;
    case Range::Length:
        if (!(f >= kMinLength && f <= kMaxLength))
            return fail("must be between " + lengthText(kMinLength) + " and " +
                        lengthText(kMaxLength) + " m" + got);
        break;
    }
    // Within its range or not, a number that is not 0 must not become 0 or lose its digits.
    if (out != 0.0 && !std::isnormal(float(out)))
        return fail("is too small for single precision (it would read as " + lengthText(f) +
                    "): " + brief(v));
    return out;
}

} // namespace

Status ObjectReader::read(std::string_view key, float& out, Range range) const {
    if (!has(key)) return {};
    Result<double> d = numberFromJson(at(key), where(key), range);
    RUBBLE_TRY(d);
    out = float(*d);
    return {};
}

Status ObjectReader::read(std::string_view key, std::int64_t& out, std::int64_t min,
                          std::int64_t max) const {
    if (!has(key)) return {};
    const Json& v = at(key);
    if (!v.is_number_integer())
        return fail(key, "expected an integer, got " + typeName(v) + " " + brief(v));
    const std::int64_t i = v.get<std::int64_t>();
    if (i < min || i > max)
        return fail(key, "must be between " + std::to_string(min) + " and " +
                             std::to_string(max) + ", got " + brief(v));
    out = i;
    return {};
}

Status ObjectReader::read(std::string_view key, bool& out) const {
    if (!has(key)) return {};
    const Json& v = at(key);
    if (!v.is_boolean())
        return fail(key, "expected true or false, got " + typeName(v) + " " + brief(v));
    out = v.get<bool>();
    return {};
}

Status ObjectReader::read(std::string_view key, std::string& out) const {
    if (!has(key)) return {};
    const Json& v = at(key);
    if (!v.is_string()) return fail(key, "expected a string, got " + typeName(v) + " " + brief(v));
    out = v.get<std::string>();
    return {};
}

Status ObjectReader::read(std::string_view key, glm::vec3& out, Range range) const {
    if (!has(key)) return {};
    Result<glm::vec3> v = vec3FromJson(at(key), where(key), range);
    RUBBLE_TRY(v);
    out = *v;
    return {};
}

Result<glm::vec3> vec3FromJson(const Json& value, const std::string& where, Range range) {
    if (!value.is_array() || value.size() != 3)
        return makeError(ErrorKind::BadInput, where,
                         "expected an array of 3 numbers, got " + brief(value));
    glm::vec3 r(0.0f);
    for (std::size_t i = 0; i < 3; ++i) {
        Result<double> d = numberFromJson(value[i], where + indexPath(i), range);
        RUBBLE_TRY(d);
        r[int(i)] = float(*d);
    }
    return r;
}

Status ObjectReader::readQuaternion(std::string_view key, glm::quat& out) const {
    if (!has(key)) return {};
    const Json& v = at(key);
    if (!v.is_array() || v.size() != 4)
        return fail(key, "expected a quaternion [w, x, y, z], got " + brief(v));
    double q[4];
    for (std::size_t i = 0; i < 4; ++i) {
        Result<double> d = numberFromJson(v[i], where(key) + indexPath(i), Range::Finite);
        RUBBLE_TRY(d);
        q[i] = *d;
    }
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (norm < 1e-6)
        return fail(key, "the quaternion " + brief(v) + " has zero length and cannot be normalised");
    out = glm::quat(float(q[0] / norm), float(q[1] / norm), float(q[2] / norm),
                    float(q[3] / norm));
    return {};
}

Status ObjectReader::readDirection(std::string_view key, glm::vec3& out) const {
    if (!has(key)) return {};
    glm::vec3 d(0.0f);
    RUBBLE_TRY(read(key, d));
    const float len = glm::length(d);
    if (!(len > 1e-6f)) return fail(key, "a direction must not have zero length, got " + brief(at(key)));
    out = d / len;
    return {};
}

namespace {

// A JSON value as a value of the option's kind; its range is checked by the table.
Result<OptionValue> optionValueFromJson(OptionKind kind, const Json& v, const std::string& where) {
    auto fail = [&](std::string expected) {
        return makeError(ErrorKind::BadInput, where,
                         "expected " + expected + ", got " + typeName(v) + " " + brief(v));
    };
    switch (kind) {
    case OptionKind::Number:
        if (!v.is_number()) return fail("a number");
        return OptionValue(v.get<double>());
    case OptionKind::WholeNumber:
        if (!v.is_number_integer()) return fail("an integer");
        // Above the int64 range: as large as it gets, for the range check to refuse.
        if (v.is_number_unsigned() &&
            v.get<std::uint64_t>() > std::uint64_t(std::numeric_limits<std::int64_t>::max()))
            return OptionValue(std::numeric_limits<std::int64_t>::max());
        return OptionValue(v.get<std::int64_t>());
    case OptionKind::Bool:
        if (!v.is_boolean()) return fail("true or false");
        return OptionValue(v.get<bool>());
    case OptionKind::Choice:
    case OptionKind::Text:
        if (!v.is_string()) return fail("a string");
        return OptionValue(v.get<std::string>());
    case OptionKind::Vec3: {
        if (!v.is_array() || v.size() != 3)
            return makeError(ErrorKind::BadInput, where,
                             "expected an array of 3 numbers, got " + brief(v));
        glm::dvec3 r(0.0);
        for (std::size_t i = 0; i < 3; ++i) {
            if (!v[i].is_number())
                return makeError(ErrorKind::BadInput, where + indexPath(i),
                                 "expected a number, got " + typeName(v[i]) + " " + brief(v[i]));
            r[int(i)] = v[i].get<double>();
        }
        return OptionValue(r);
    }
    }
    return makeError(ErrorKind::Internal, where, "unknown option kind");
}

} // namespace

Status ObjectReader::readOption(std::string_view key, const Option& option,
                                OptionTarget target) const {
    if (!has(key)) return {};
    Result<OptionValue> v = optionValueFromJson(option.kind, at(key), where(key));
    RUBBLE_TRY(v);
    return assignOption(option, *v, where(key), target);
}

} // namespace rubble
