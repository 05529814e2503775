#pragma once
// What panels may ask of the application: show a message, ask for a line of
// text, ask for a yes/no over a list (a diff before it is sent).
#include <functional>
#include <string>
#include <vector>

#include "app/tui/screen.hpp"

namespace nlsoft::console::tui {

struct Ui {
  virtual ~Ui() = default;
  virtual void message(const std::string& text, Role role = Role::Normal) = 0;
  virtual void prompt(const std::string& label, const std::string& initial,
                      std::function<void(const std::string&)> done) = 0;
  virtual void confirm(const std::string& title, std::vector<std::string> lines, std::function<void()> yes) = 0;
};

}  // namespace nlsoft::console::tui
