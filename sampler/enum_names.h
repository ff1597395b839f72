#pragma once
// One {name, value} table per enum and the one parse/format over it, so that
// every enum reads and writes its names the same way and every unknown name
// gets the same message: "unknown box kind 'x' (expected multicorner,
// anchored or twopoint)".
//
// The first entry of a value is its name (what toString writes and the
// message lists); later entries of the same value are accepted aliases. An
// enum opts in by an enumNames(E) function beside it (found by ADL) that
// returns its table; toString(E) and parseEnum<E> then work for it.

#include <array>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace nuld {

// "a", "a or b", "a, b or c".
std::string joinAlternatives(const std::vector<std::string> &names);

// The name in `names` closest to `word` by edit distance, when it is close
// enough to be a likely typo (at most a third of the word's letters wrong);
// else "".
std::string closestName(const std::string &word, const std::vector<std::string> &names);
// " (did you mean 'NAME'?)" for closestName's answer, else "".
std::string didYouMean(const std::string &word, const std::vector<std::string> &names);

template <class E>
struct EnumEntry {
  std::string_view name;
  E value;
};

template <class E, std::size_t N>
struct EnumTable {
  using Entry = EnumEntry<E>;
  std::string_view what;  // what the names name, for messages: "box kind"
  std::array<Entry, N> entries;

  constexpr std::optional<E> find(std::string_view text) const {
    for (const Entry &e : entries)
      if (e.name == text) return e.value;
    return std::nullopt;
  }
  // Throws std::invalid_argument naming `what`, the text and the names.
  E parse(std::string_view text) const {
    if (const auto v = find(text)) return *v;
    throw std::invalid_argument("unknown " + std::string(what) + " '" + std::string(text) + "'" +
                                didYouMean(std::string(text), names()) + " (expected " +
                                expected() + ")");
  }
  constexpr std::string_view name(E value) const {
    for (const Entry &e : entries)
      if (e.value == value) return e.name;
    return "?";
  }
  // The names without aliases, in table order.
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (std::size_t k = 0; k < N; ++k)
      if (name(entries[k].value) == entries[k].name) out.emplace_back(entries[k].name);
    return out;
  }
  std::string expected() const { return joinAlternatives(names()); }
};

// enumTable<BoxKind>("box kind", {{"multicorner", BoxKind::MultipleCorner}, ...})
template <class E, std::size_t N>
constexpr EnumTable<E, N> enumTable(std::string_view what, const EnumEntry<E> (&entries)[N]) {
  EnumTable<E, N> t{what, {}};
  for (std::size_t k = 0; k < N; ++k) t.entries[k] = entries[k];
  return t;
}

template <class E>
concept NamedEnum = requires(E e) {
  enumNames(e).parse(std::string_view());
};

template <NamedEnum E>
std::string toString(E value) {
  return std::string(enumNames(value).name(value));
}

template <NamedEnum E>
E parseEnum(std::string_view text) {
  return enumNames(E{}).parse(text);
}

}  // namespace nuld
