// A parsed COLLADA file with everything the element readers need: lookup by
// id, strict number parsing, and errors and warnings that name the file, the
// line and the element. Every reader in io/collada_*.cpp works through it.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <pugixml.hpp>

#include "kernels/math/vec3.h"
#include "scene_error.h"

namespace pt {

class ColladaDocument {
 public:
  /// Parses `text`; `label` names the file in messages. Throws InputError.
  ColladaDocument(std::string label, std::string text);
  ColladaDocument(const ColladaDocument&) = delete;
  ColladaDocument& operator=(const ColladaDocument&) = delete;

  pugi::xml_node root() const { return doc_.document_element(); }
  const std::string& label() const { return label_; }

  /// The element with this id ("#id" or "id"); fails naming `from` if absent,
  /// or if several <node> elements carry the id (the reference is ambiguous).
  pugi::xml_node resolve(pugi::xml_node from, std::string_view url) const;
  /// The element with this id, or an empty node; fails on an ambiguous id.
  pugi::xml_node find(std::string_view url) const;

  /// Whether a <technique profile="..."> is the course's: "CGL", or "CMU462"
  /// as the course's earlier offerings wrote it.
  static bool is_course_profile(std::string_view profile) { return profile == "CGL" || profile == "CMU462"; }

  [[noreturn]] void fail(pugi::xml_node where, const std::string& what) const;
  /// Records a one-line warning; repeats of the same line (the same element
  /// reached through several instances) are dropped, and after kMaxWarnings
  /// distinct lines the rest are only counted.
  void warn(pugi::xml_node where, const std::string& what);
  /// The warnings, plus one line saying how many were not kept, if any.
  std::vector<std::string> warnings() const;

  /// All numbers in the element's text; every one must be finite.
  std::vector<float> floats(pugi::xml_node element) const;
  /// Exactly `n` finite numbers.
  std::vector<float> floats(pugi::xml_node element, size_t n) const;
  /// The first three numbers of a colour or vector (a fourth, alpha, is ignored).
  float3 color(pugi::xml_node element) const;
  /// A single finite number, or `fallback` when the element is absent.
  float scalar(pugi::xml_node element, float fallback) const;
  /// Non-negative integers, each < `limit`.
  std::vector<uint32_t> indices(pugi::xml_node element, uint64_t limit, const char* what) const;
  /// A non-negative integer attribute no larger than `limit`; `fallback` when absent.
  uint64_t count_attribute(pugi::xml_node element, const char* name, uint64_t fallback, uint64_t limit) const;

  /// "<tag id="x">" or "<tag>" for messages.
  std::string describe(pugi::xml_node element) const;

 private:
  int line_of(pugi::xml_node element) const;
  int line_of_offset(ptrdiff_t offset) const;

  std::string label_;
  std::string text_;
  pugi::xml_document doc_;
  std::vector<size_t> line_starts_;
  std::unordered_map<std::string_view, pugi::xml_node> ids_;
  /// Ids that two or more <node> elements carry: "defined on lines a and b".
  std::unordered_map<std::string_view, std::string> ambiguous_ids_;
  std::vector<std::string> warnings_;
  std::unordered_set<std::string> warned_;
  size_t warnings_dropped_ = 0;
};

/// Largest magnitude a world-space coordinate may have: products of two
/// coordinates (intersection tests, BVH surface areas) then stay far below
/// the float range.
constexpr float kMaxCoordinate = 1e15f;
constexpr size_t kMaxWarnings = 100;

/// Finite and within +-kMaxCoordinate on every axis.
inline bool within_coordinate_limit(float3 p) {
  return std::fabs(p.x) <= kMaxCoordinate && std::fabs(p.y) <= kMaxCoordinate && std::fabs(p.z) <= kMaxCoordinate;
}

}  // namespace pt
