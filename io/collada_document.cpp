// ColladaDocument: parsing, id index, messages and strict number lists.
#include "collada_document.h"

#include <algorithm>
#include <charconv>
#include <cmath>

#include "scene_error.h"
#include "strict_number.h"

namespace pt {
namespace {

bool is_space(char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t'; }

/// Calls f(token) for each whitespace-separated token of s.
template <class F>
void for_each_token(std::string_view s, F&& f) {
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && is_space(s[i])) ++i;
    size_t j = i;
    while (j < s.size() && !is_space(s[j])) ++j;
    if (j > i) f(s.substr(i, j - i));
    i = j;
  }
}

/// Where a parse error is, for its message: "at \"<text>\"" or "at the end of the file".
std::string text_at(std::string_view text, ptrdiff_t offset) {
  if (offset < 0 || static_cast<size_t>(offset) >= text.size()) return "at the end of the file";
  std::string_view rest = text.substr(static_cast<size_t>(offset));
  return "at \"" + excerpt(rest.substr(0, rest.find('\n')), 24) + "\"";
}

}  // namespace

ColladaDocument::ColladaDocument(std::string label, std::string text)
    : label_(std::move(label)), text_(std::move(text)) {
  line_starts_.push_back(0);
  for (size_t i = 0; i < text_.size(); ++i)
    if (text_[i] == '\n') line_starts_.push_back(i + 1);

  pugi::xml_parse_result r = doc_.load_buffer(text_.data(), text_.size(), pugi::parse_default, pugi::encoding_utf8);
  if (!r)
    throw InputError(label_ + ":" + std::to_string(line_of_offset(r.offset)) + ": malformed XML " +
                     text_at(text_, r.offset) + ": " + r.description());
  pugi::xml_node top = doc_.document_element();
  if (!top) throw InputError(label_ + ": no root element");
  if (std::string_view(top.name()) != "COLLADA")
    throw InputError(label_ + ":" + std::to_string(line_of(top)) + ": root element is <" + excerpt(top.name()) +
                     ">, expected <COLLADA>");

  // Index ids iteratively (deep nesting must not exhaust the stack).
  std::vector<pugi::xml_node> stack{top};
  while (!stack.empty()) {
    pugi::xml_node n = stack.back();
    stack.pop_back();
    if (pugi::xml_attribute id = n.attribute("id")) {
      auto [it, inserted] = ids_.emplace(id.value(), n);
      if (!inserted) {
        pugi::xml_node later = line_of(n) > line_of(it->second) ? n : it->second;
        pugi::xml_node earlier = later == n ? it->second : n;
        bool both_nodes = std::string_view(n.name()) == "node" && std::string_view(it->second.name()) == "node";
        if (!both_nodes)
          fail(later,
               "id \"" + excerpt(id.value()) + "\" is already defined on line " + std::to_string(line_of(earlier)));
        // The course renderer keeps every node (it walks the tree); only a reference to the id is ambiguous.
        auto [amb, first] = ambiguous_ids_.emplace(id.value(), "defined on lines " + std::to_string(line_of(earlier)) +
                                                                   " and " + std::to_string(line_of(later)));
        if (!first) amb->second += " (and more)";
      }
    }
    for (pugi::xml_node c = n.first_child(); c; c = c.next_sibling())
      if (c.type() == pugi::node_element) stack.push_back(c);
  }
  if (!ambiguous_ids_.empty()) {
    auto first = std::min_element(ambiguous_ids_.begin(), ambiguous_ids_.end(),
                                  [](const auto& a, const auto& b) { return a.first < b.first; });
    warn({}, std::to_string(ambiguous_ids_.size()) + " id(s) carried by more than one <node> (\"" +
                 excerpt(first->first) + "\", " + first->second +
                 "); every node is kept, as the course renderer keeps them, and a reference to such an id is refused");
  }
}

pugi::xml_node ColladaDocument::find(std::string_view url) const {
  if (!url.empty() && url.front() == '#') url.remove_prefix(1);
  if (auto amb = ambiguous_ids_.find(url); amb != ambiguous_ids_.end())
    fail({}, "a reference to id \"" + excerpt(url) + "\" is ambiguous: several <node> elements carry it (" +
                 amb->second + ")");
  auto it = ids_.find(url);
  return it == ids_.end() ? pugi::xml_node() : it->second;
}

pugi::xml_node ColladaDocument::resolve(pugi::xml_node from, std::string_view url) const {
  std::string_view id = url;
  if (!id.empty() && id.front() == '#') id.remove_prefix(1);
  if (auto amb = ambiguous_ids_.find(id); amb != ambiguous_ids_.end())
    fail(from, "refers to \"" + excerpt(url) + "\", which several <node> elements carry (" + amb->second +
                   "): the reference is ambiguous");
  pugi::xml_node n = find(url);
  if (!n) fail(from, "refers to \"" + excerpt(url) + "\", which no element defines");
  return n;
}

int ColladaDocument::line_of_offset(ptrdiff_t offset) const {
  if (offset < 0) return 0;
  auto it = std::upper_bound(line_starts_.begin(), line_starts_.end(), static_cast<size_t>(offset));
  return static_cast<int>(it - line_starts_.begin());
}

int ColladaDocument::line_of(pugi::xml_node element) const { return line_of_offset(element.offset_debug()); }

std::string ColladaDocument::describe(pugi::xml_node e) const {
  std::string s(1, '<');
  s += excerpt(e.name());
  for (const char* attr : {"id", "sid", "material", "url", "source", "semantic"})
    if (pugi::xml_attribute a = e.attribute(attr)) {
      s += std::string(" ") + attr + "=\"" + excerpt(a.value()) + "\"";
      break;
    }
  return s + ">";
}

void ColladaDocument::fail(pugi::xml_node where, const std::string& what) const {
  if (!where) throw InputError(label_ + ": " + what);
  throw InputError(label_ + ":" + std::to_string(line_of(where)) + ": " + describe(where) + ": " + what);
}

void ColladaDocument::warn(pugi::xml_node where, const std::string& what) {
  std::string w = label_;
  if (where) w += std::string(":") + std::to_string(line_of(where)) + ": " + describe(where);
  std::string line = printable_line(w + ": " + what);
  if (warned_.size() >= kMaxWarnings) {
    if (!warned_.count(line)) ++warnings_dropped_;
    return;
  }
  if (warned_.insert(line).second) warnings_.push_back(std::move(line));
}

std::vector<std::string> ColladaDocument::warnings() const {
  std::vector<std::string> all = warnings_;
  if (warnings_dropped_ > 0)
    all.push_back(label_ + ": " + std::to_string(warnings_dropped_) + " further warnings not shown");
  return all;
}

std::vector<float> ColladaDocument::floats(pugi::xml_node element) const {
  std::vector<float> out;
  for_each_token(element.child_value(), [&](std::string_view tok) {
    float v = 0.0f;
    Number n = parse_float(tok, v);
    if (n == Number::kOutOfRange) fail(element, "number \"" + excerpt(tok) + "\" is out of float range");
    if (n == Number::kNotANumber) fail(element, "\"" + excerpt(tok) + "\" is not a number");
    if (!std::isfinite(v)) fail(element, "non-finite number \"" + excerpt(tok) + "\"");
    out.push_back(v);
  });
  return out;
}

std::vector<float> ColladaDocument::floats(pugi::xml_node element, size_t n) const {
  std::vector<float> v = floats(element);
  if (v.size() != n) fail(element, "holds " + std::to_string(v.size()) + " numbers, expected " + std::to_string(n));
  return v;
}

float3 ColladaDocument::color(pugi::xml_node element) const {
  std::vector<float> v = floats(element);
  if (v.size() != 3 && v.size() != 4)
    fail(element, "holds " + std::to_string(v.size()) + " numbers, expected 3 (or 4 with alpha)");
  return {v[0], v[1], v[2]};
}

float ColladaDocument::scalar(pugi::xml_node element, float fallback) const {
  if (!element) return fallback;
  return floats(element, 1)[0];
}

std::vector<uint32_t> ColladaDocument::indices(pugi::xml_node element, uint64_t limit, const char* what) const {
  std::vector<uint32_t> out;
  for_each_token(element.child_value(), [&](std::string_view tok) {
    uint64_t v = 0;
    auto [end, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    if (!tok.empty() && tok.front() == '-')
      fail(element, std::string("negative ") + what + " \"" + excerpt(tok) + "\"");
    if (ec == std::errc::result_out_of_range && end == tok.data() + tok.size())
      fail(element, std::string(what) + " \"" + excerpt(tok) + "\" is out of range");
    if (ec != std::errc() || end != tok.data() + tok.size())
      fail(element, "\"" + excerpt(tok) + "\" is not a non-negative integer");
    if (v >= limit)
      fail(element,
           std::string(what) + " " + std::to_string(v) + " is out of range (" + std::to_string(limit) + " available)");
    out.push_back(static_cast<uint32_t>(v));
  });
  return out;
}

uint64_t ColladaDocument::count_attribute(pugi::xml_node element, const char* name, uint64_t fallback,
                                          uint64_t limit) const {
  pugi::xml_attribute a = element.attribute(name);
  if (!a) return fallback;
  std::string_view s = a.value();
  uint64_t v = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec == std::errc::result_out_of_range && end == s.data() + s.size())
    fail(element, std::string(name) + "=\"" + excerpt(s) + "\" is larger than the data it describes");
  if (ec != std::errc() || end != s.data() + s.size() || s.empty())
    fail(element, std::string(name) + "=\"" + excerpt(s) + "\" is not a non-negative integer");
  if (v > limit) fail(element, std::string(name) + "=\"" + excerpt(s) + "\" is larger than the data it describes");
  return v;
}

}  // namespace pt
