// What a material model's parser sees of its entry in the deck's `materials` list: values checked, errors name
// the key (the deck parser, deck_materials.cpp, implements it). A model reads its own keys through it into its
// MaterialSpec (materials/*.h) without knowing the deck's format.
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace sph {

class MaterialKeys {
 public:
  MaterialKeys(const nlohmann::json& j, std::string path, unsigned terms) : j_(j), path_(std::move(path)), terms_(terms) {}
  bool has(const std::string& key) const;
  double positive(const std::string& key) const;  // required, > 0
  double non_negative_or(const std::string& key, double fallback) const;  // optional, >= 0
  double non_negative(const std::string& key) const;                      // required, >= 0
  double positive_or(const std::string& key, double fallback) const;     // optional, > 0
  double number(const std::string& key) const;                           // required, finite
  double number_or(const std::string& key, double fallback) const;       // optional, finite
  // Optional text, one of `allowed`.
  std::string text_or(const std::string& key, const std::string& fallback, const std::vector<std::string>& allowed) const;
  // Optional object `key` with only `allowed` keys, as MaterialKeys (none when absent).
  std::optional<MaterialKeys> object(const std::string& key, const std::vector<std::string>& allowed) const;
  // Reject the value of `key`: "'<path>.<key>' <what>".
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  // The entries of list `key` (required, min_size..max_size objects with only `allowed` keys), each as MaterialKeys.
  std::vector<MaterialKeys> objects(const std::string& key, std::size_t min_size, std::size_t max_size,
                                    const std::vector<std::string>& allowed) const;
  // Required exactly when the physics term `bit` (named `term`) is on; 0 otherwise.
  double positive_with_term(const std::string& key, unsigned bit, const std::string& term) const;
  const std::string& path() const { return path_; }
  bool term_on(unsigned bit) const { return (terms_ & bit) != 0; }  // physics term `bit` is in the deck

 private:
  const nlohmann::json& j_;
  std::string path_;
  unsigned terms_;
};

}  // namespace sph
