// samples/app/params.hpp - a sample's settings by name. A sample binds the fields of its technique's
// Settings struct once (a choice of named values, an on/off switch, a number in a range); the same
// bindings parse `--param name=value`, draw the panel's widgets and let the report sweep settings by
// name (`method=lispsm scissor=on`). Unknown names and values are errors that list the valid ones.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace app {

class Params {
public:
    struct Entry {
        std::string name;
        enum class Kind { Choice, Toggle, Number } kind = Kind::Number;
        std::vector<std::string> options;       // Choice: the names, in order
        double min = 0.0, max = 0.0;            // Number: inclusive range
        bool integer = false;                   // Number: whole numbers only
        std::function<std::string()> get;       // the current value as text
        std::function<double()> get_number;     // Number: the current value
        std::function<void(std::size_t)> set_choice;
        std::function<void(double)> set_number;
    };

    /// A field that takes one of several named values (an enum, or an index).
    template <class T>
    void choice(const std::string& name, T* field, const std::vector<std::pair<std::string, T>>& values) {
        Entry e;
        e.name = name;
        e.kind = Entry::Kind::Choice;
        for (const auto& v : values) e.options.push_back(v.first);
        e.get = [field, values] {
            for (const auto& v : values)
                if (*field == v.second) return v.first;
            return std::string("?");
        };
        e.set_choice = [field, values](std::size_t i) { *field = values[i].second; };
        entries_.push_back(std::move(e));
    }
    /// An on/off switch (`name=on` or `name=off`).
    void toggle(const std::string& name, bool* field) {
        choice<bool>(name, field, {{"off", false}, {"on", true}});
        entries_.back().kind = Entry::Kind::Toggle;  // a checkbox in the panel; "off" / "on" on the command line
    }
    /// A number in [min, max] (integer: whole numbers only).
    template <class T>
    void number(const std::string& name, T* field, double min, double max) {
        Entry e;
        e.name = name;
        e.kind = Entry::Kind::Number;
        e.min = min;
        e.max = max;
        e.integer = std::is_integral<T>::value;
        e.get = [field] {
            char b[32];
            std::snprintf(b, sizeof b, "%g", static_cast<double>(*field));
            return std::string(b);
        };
        e.get_number = [field] { return static_cast<double>(*field); };
        e.set_number = [field](double v) { *field = static_cast<T>(v); };
        entries_.push_back(std::move(e));
    }

    /// Sets `name` from text; false with a message that lists what is valid.
    bool set(const std::string& name, const std::string& value, std::string& why) {
        Entry* e = find(name);
        if (!e) {
            why = "unknown parameter '" + name + "'; valid: " + names();
            return false;
        }
        if (e->kind != Entry::Kind::Number) {
            const auto it = std::find(e->options.begin(), e->options.end(), value);
            if (it == e->options.end()) {
                why = "'" + value + "' is not a value of " + name + "; valid: " + join(e->options);
                return false;
            }
            e->set_choice(static_cast<std::size_t>(it - e->options.begin()));
            return true;
        }
        char* end = nullptr;
        const double v = std::strtod(value.c_str(), &end);
        if (value.empty() || end == nullptr || *end != '\0' || !std::isfinite(v) || v < e->min || v > e->max ||
            (e->integer && v != std::floor(v))) {
            char b[96];
            std::snprintf(b, sizeof b, "%s wants %s in [%g, %g], not '%s'", name.c_str(),
                          e->integer ? "a whole number" : "a number", e->min, e->max, value.c_str());
            why = b;
            return false;
        }
        e->set_number(v);
        return true;
    }
    /// Parses "name=value".
    bool set(const std::string& assignment, std::string& why) {
        const auto eq = assignment.find('=');
        if (eq == std::string::npos) {
            why = "--param wants name=value, not '" + assignment + "'; valid names: " + names();
            return false;
        }
        return set(assignment.substr(0, eq), assignment.substr(eq + 1), why);
    }

    /// "method=lispsm size=1024 ..." (every bound field, in binding order).
    std::string label() const {
        std::string s;
        for (const auto& e : entries_) s += (s.empty() ? "" : " ") + e.name + "=" + e.get();
        return s;
    }
    std::string names() const {
        std::vector<std::string> n;
        for (const auto& e : entries_) n.push_back(e.name);
        return join(n);
    }
    std::vector<Entry>& entries() { return entries_; }
    const std::vector<Entry>& entries() const { return entries_; }

private:
    Entry* find(const std::string& name) {
        for (auto& e : entries_)
            if (e.name == name) return &e;
        return nullptr;
    }
    static std::string join(const std::vector<std::string>& v) {
        std::string s;
        for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
        return s.empty() ? "(none)" : s;
    }
    std::vector<Entry> entries_;
};

}  // namespace app
