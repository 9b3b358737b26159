// Parameter file: patterns, declaration, reading and printing (see parameter_file.h).
#include "common/parameter_file.h"
#include "common/shown_text.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <istream>
#include <map>
#include <sstream>
#include <type_traits>

namespace hertzgear
{
  namespace
  {
    bool only_white_space_left(std::istream &in)
    {
      char c;
      return !(in >> c);
    }

    std::string trim(const std::string &text)
    {
      const auto b = text.find_first_not_of(" \t");
      if (b == std::string::npos)
        return "";
      const auto e = text.find_last_not_of(" \t");
      return text.substr(b, e - b + 1);
    }

    // Default stream formatting (6 significant digits: 4.17e+08, 1e-10, 0.1172), with more digits
    // only where 6 would not read back as the same number.
    std::string format_number(const double value)
    {
      for (int digits = 6; digits <= 17; ++digits)
        {
          std::ostringstream os;
          os << std::setprecision(digits) << value;
          std::istringstream in(os.str());
          double             back = 0;
          if (digits == 17 || ((in >> back) && back == value))
            return os.str();
        }
      return ""; // not reached
    }

    std::string format_number(const int value)
    {
      std::ostringstream os;
      os << value;
      return os.str();
    }

    // The help text as comment lines of at most `width` characters where the words allow;
    // a word longer than that stands on its own line.
    std::vector<std::string> break_into_lines(std::string text, const std::size_t width)
    {
      std::vector<std::string> lines;
      const auto               drop_trailing_spaces = [](std::string &s) {
        while (!s.empty() && s.back() == ' ')
          s.pop_back();
      };
      drop_trailing_spaces(text);
      while (!text.empty())
        {
          while (!text.empty() && text.front() == ' ')
            text.erase(0, 1);
          const auto newline = text.find('\n');
          if (newline != std::string::npos && newline <= width)
            {
              std::string line = text.substr(0, newline);
              drop_trailing_spaces(line);
              lines.push_back(line);
              text.erase(0, newline + 1);
              continue;
            }
          if (text.size() < width)
            {
              drop_trailing_spaces(text);
              lines.push_back(text);
              text.clear();
            }
          else
            {
              // the last space at or before `width`, else the first one after it
              std::size_t at = std::min(width, text.size() - 1);
              while (at > 0 && text[at] != ' ')
                --at;
              if (at == 0)
                {
                  at = std::min(width, text.size() - 1);
                  while (at < text.size() && text[at] != ' ')
                    ++at;
                }
              std::string line = text.substr(0, at);
              drop_trailing_spaces(line);
              lines.push_back(line);
              text.erase(0, at);
            }
        }
      return lines;
    }

    // Names with every character other than a letter or digit written as _xx (its hex code):
    // the alphabetical order of the printed parameters is the order of these strings.
    std::string sort_key(const std::string &name)
    {
      static const char hex[] = "0123456789abcdef";
      std::string       key;
      for (const char c : name)
        {
          const auto u = static_cast<unsigned char>(c);
          if ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9'))
            key += c;
          else
            {
              key += '_';
              key += hex[u / 16];
              key += hex[u % 16];
            }
        }
      return key;
    }

    std::string hex_code(const char c)
    {
      std::ostringstream os;
      os << "0x" << std::hex << std::setw(2) << std::setfill('0')
         << static_cast<unsigned int>(static_cast<unsigned char>(c));
      return os.str();
    }

    bool is_control(const char c)
    {
      const auto u = static_cast<unsigned char>(c);
      return (u < 0x20 && c != '\t') || u == 0x7f;
    }

    // The refusal of a value longer than ParameterFile::max_value_length, naming the key.
    std::string value_too_long(const std::string &name, const std::size_t length,
                               const std::string &what = "value")
    {
      return msg(name, ": the ", what, " is ", length, " characters long, more than the ",
                 ParameterFile::max_value_length, " characters a scene ", what, " can have");
    }
  } // namespace

  namespace patterns
  {
    template <typename T>
    Range<T>::Range(const T lower_, const T upper_) : lower(lower_), upper(upper_)
    {
      if (!(lower <= upper) || !std::isfinite(double(lower)) || !std::isfinite(double(upper)))
        throw std::logic_error("patterns::Integer/Double: bounds must be finite and ordered");
    }

    template <typename T>
    bool Range<T>::match(const std::string &text) const
    {
      std::istringstream in(text);
      T                  v = 0;
      if (!(in >> v) || !only_white_space_left(in) || !std::isfinite(double(v)))
        return false;
      return lower <= v && v <= upper;
    }

    template <typename T>
    std::string Range<T>::description() const
    {
      std::ostringstream os;
      os << (std::is_integral_v<T> ? "[Integer range " : "[Double ") << lower << "..." << upper
         << " (inclusive)]";
      return os.str();
    }

    template class Range<int>;
    template class Range<double>;

    bool Bool::match(const std::string &text) const { return text == "true" || text == "false"; }
    std::string Bool::description() const { return "[Bool]"; }

    Selection::Selection(const std::string &choices_)
      : choices(choices_)
    {
      for (const std::string spaced : {" |", "| "})
        for (auto at = choices.find(spaced); at != std::string::npos; at = choices.find(spaced))
          choices.replace(at, 2, "|");
    }

    bool Selection::match(const std::string &text) const
    {
      std::string::size_type begin = 0;
      while (true)
        {
          const auto end = choices.find('|', begin);
          if (choices.compare(begin, end == std::string::npos ? std::string::npos : end - begin,
                              text) == 0)
            return true;
          if (end == std::string::npos)
            return false;
          begin = end + 1;
        }
    }

    std::string Selection::description() const { return "[Selection " + choices + " ]"; }

    bool        Anything::match(const std::string &) const { return true; }
    std::string Anything::description() const { return "[Anything]"; }

    List::List(const Pattern &element, const unsigned int min_length_,
               const unsigned int max_length_, const std::string &separator)
      : element_pattern(element.clone()), min_length(min_length_), max_length(max_length_),
        sep(separator)
    {
      if (min_length > max_length || sep.empty())
        throw std::logic_error("patterns::List: needs min_length <= max_length and a separator");
    }

    List::List(const List &other)
      : element_pattern(other.element_pattern->clone()), min_length(other.min_length),
        max_length(other.max_length), sep(other.sep)
    {}

    bool List::match(const std::string &text) const
    {
      const auto items = split_list(text, sep);
      if (items.size() < min_length || items.size() > max_length)
        return false;
      return std::all_of(items.begin(), items.end(),
                         [&](const std::string &item) { return element_pattern->match(item); });
    }

    std::string List::description() const
    {
      std::ostringstream os;
      os << "[List of <" << element_pattern->description() << "> of length " << min_length
         << "..." << max_length << " (inclusive)";
      if (sep != ",")
        os << " separated by <" << sep << ">";
      os << "]";
      return os.str();
    }

    std::vector<std::string> split_list(const std::string &text, const std::string &separator)
    {
      std::string rest = text;
      while (!rest.empty() && rest.back() == ' ')
        rest.pop_back();
      std::vector<std::string> items;
      while (!rest.empty())
        {
          std::string item;
          const auto  at = rest.find(separator);
          if (at == std::string::npos)
            {
              item = rest;
              rest.clear();
            }
          else
            {
              item = rest.substr(0, at);
              rest.erase(0, at + separator.size());
            }
          const auto b = item.find_first_not_of(' ');
          item = b == std::string::npos ? "" : item.substr(b, item.find_last_not_of(' ') - b + 1);
          items.push_back(item);
        }
      return items;
    }
  } // namespace patterns

  namespace
  {
    std::string error_text(const std::string &source, const unsigned int line,
                           const std::string &text)
    {
      if (source.empty())
        return text;
      if (line == 0)
        return source + ": " + text;
      return source + ", line " + std::to_string(line) + ": " + text;
    }
  } // namespace

  ParameterFileError::ParameterFileError(const std::string &source, const unsigned int line,
                                         const std::string &text)
    : InputError(error_text(source, line, text)), source_name(source), line_number(line),
      message(text)
  {}

  struct ParameterFile::Section
  {
    std::string                           name; // empty at the top level
    Section                              *parent = nullptr;
    std::vector<std::unique_ptr<Entry>>   entries;
    std::vector<std::unique_ptr<Section>> subsections;

    std::string path() const
    {
      if (parent == nullptr)
        return "";
      const std::string above = parent->path();
      return above.empty() ? name : above + "/" + name;
    }
    // "in subsection \"Gear pair/Pinion\"" or "at the top level", for messages
    std::string where() const
    {
      return parent == nullptr ? "at the top level" : "in subsection \"" + path() + "\"";
    }

    Entry *entry(const std::string &key) const
    {
      for (const auto &e : entries)
        if (e->name == key)
          return e.get();
      return nullptr;
    }
    Section *subsection(const std::string &sub) const
    {
      for (const auto &s : subsections)
        if (s->name == sub)
          return s.get();
      return nullptr;
    }
  };

  ParameterFile::ParameterFile()
    : root(std::make_unique<Section>())
  {
    path.push_back(root.get());
  }

  ParameterFile::~ParameterFile() = default;

  void ParameterFile::enter_subsection(const std::string &name, const std::string &help)
  {
    if (name.empty() || name != trim(name) || name.find('/') != std::string::npos ||
        name.find('#') != std::string::npos)
      throw std::logic_error("ParameterFile: bad subsection name \"" + name + "\"");
    Section *current = path.back();
    Section *sub     = current->subsection(name);
    if (sub == nullptr)
      {
        current->subsections.push_back(std::make_unique<Section>());
        sub         = current->subsections.back().get();
        sub->name   = name;
        sub->parent = current;
      }
    path.push_back(sub);
    if (!help.empty())
      section_help.emplace_back(sub->path(), help);
  }

  void ParameterFile::leave_subsection()
  {
    if (path.size() < 2)
      throw std::logic_error("ParameterFile: leave_subsection() at the top level");
    path.pop_back();
  }

  ParameterFile::Entry &
  ParameterFile::declare(const std::string &key, const patterns::Pattern &pattern,
                         const std::string &help, const std::string &default_value,
                         std::function<void(const std::string &)> assign_value)
  {
    Section *current = path.back();
    if (key.empty() || key != trim(key) || key.find_first_of("=#/") != std::string::npos)
      throw std::logic_error("ParameterFile: bad key \"" + key + "\"");
    if (current->entry(key) != nullptr)
      throw std::logic_error("ParameterFile: " + key + " declared twice " + current->where());
    if (help.empty())
      throw std::logic_error("ParameterFile: " + key + " needs a help text");
    if (default_value.find('#') != std::string::npos ||
        std::any_of(default_value.begin(), default_value.end(), is_control))
      throw std::logic_error("ParameterFile: the default of " + key +
                             " cannot be written in a parameter file");
    if (!pattern.match(default_value))
      throw std::logic_error("ParameterFile: the default \"" + default_value + "\" of " + key +
                             " does not match " + pattern.description());
    auto entry           = std::make_unique<Entry>();
    entry->name          = key;
    entry->section_path  = current->path();
    entry->documentation = help;
    entry->default_value = default_value;
    entry->value         = default_value;
    entry->allowed       = pattern.clone();
    entry->assign        = std::move(assign_value);
    current->entries.push_back(std::move(entry));
    declared.push_back(current->entries.back().get());
    return *current->entries.back();
  }

  namespace
  {
    template <typename T>
    T read_as(const std::string &text)
    {
      std::istringstream in(text);
      T                  value{};
      if (!(in >> value))
        throw std::invalid_argument("\"" + text + "\" is not a number");
      return value;
    }
  } // namespace

  const ParameterFile::Entry &ParameterFile::add(const std::string &key, int &value,
                                                 const patterns::Pattern &pattern,
                                                 const std::string       &help)
  {
    return declare(key, pattern, help, format_number(value),
                   [&value](const std::string &text) { value = read_as<int>(text); });
  }

  const ParameterFile::Entry &ParameterFile::add(const std::string &key, double &value,
                                                 const patterns::Pattern &pattern,
                                                 const std::string       &help)
  {
    return declare(key, pattern, help, format_number(value),
                   [&value](const std::string &text) { value = read_as<double>(text); });
  }

  const ParameterFile::Entry &ParameterFile::add(const std::string &key, bool &value,
                                                 const patterns::Pattern &pattern,
                                                 const std::string       &help)
  {
    return declare(key, pattern, help, value ? "true" : "false",
                   [&value](const std::string &text) { value = (text == "true"); });
  }

  const ParameterFile::Entry &ParameterFile::add(const std::string &key, std::string &value,
                                                 const patterns::Pattern &pattern,
                                                 const std::string       &help)
  {
    return declare(key, pattern, help, value, [&value](const std::string &text) { value = text; });
  }

  const ParameterFile::Entry &ParameterFile::add(const std::string &key, std::vector<double> &value,
                                                 const patterns::Pattern &pattern,
                                                 const std::string       &help)
  {
    const auto *list = dynamic_cast<const patterns::List *>(&pattern);
    if (list == nullptr || dynamic_cast<const patterns::Double *>(&list->element()) == nullptr)
      throw std::logic_error("ParameterFile: " + key + " is a list of numbers but its pattern is " +
                             pattern.description());
    const std::string separator = list->separator();
    std::string       text;
    for (const double v : value)
      text += (text.empty() ? "" : separator + " ") + format_number(v);
    return declare(key, pattern, help, text, [&value, separator](const std::string &t) {
      std::vector<double> numbers;
      for (const auto &item : patterns::split_list(t, separator))
        numbers.push_back(read_as<double>(item));
      value = numbers;
    });
  }

  void ParameterFile::assign(Entry &entry, const std::string &value, const std::string &source,
                             const unsigned int line)
  {
    const std::string name =
      entry.section_path.empty() ? entry.name : entry.section_path + "/" + entry.name;
    if (value.size() > max_value_length)
      throw ParameterFileError(source, line, value_too_long(name, value.size()));
    for (const char c : value)
      if (is_control(c))
        throw ParameterFileError(source, line,
                                 name + ": the value contains the control character " +
                                   hex_code(c));
    if (value.find('#') != std::string::npos)
      throw ParameterFileError(source, line,
                               name + " = \"" + shown(value) +
                                 "\": a value cannot contain '#', which starts a comment in a "
                                 "parameter file");
    if (!entry.allowed->match(value))
      throw ParameterFileError(source, line,
                               name + " = \"" + shown(value) + "\" is not allowed; allowed: " +
                                 entry.allowed->description());
    try
      {
        entry.assign(value);
      }
    catch (const std::exception &e)
      {
        throw ParameterFileError(source, line, name + " = \"" + shown(value) + "\": " + e.what());
      }
    entry.value = value;
  }

  void ParameterFile::parse(std::istream &in, const std::string &source)
  {
    struct Open
    {
      Section     *section;
      unsigned int line;
    };
    std::vector<Open>                  open;
    Section                           *current = root.get();
    std::map<const Entry *, unsigned>  set_on_line;
    unsigned int                       n = 0;
    const auto fail = [&](const std::string &text) { throw ParameterFileError(source, n, text); };

    for (std::string raw; std::getline(in, raw);)
      {
        ++n;
        if (!raw.empty() && raw.back() == '\r')
          raw.pop_back();
        const auto last = raw.find_last_not_of(" \t");
        if (last != std::string::npos && raw[last] == '\\')
          fail("the line ends in a backslash; continuation lines are not supported, write the "
               "statement on one line");
        std::string line = raw.substr(0, raw.find('#'));
        for (char &c : line)
          if (c == '\t')
            c = ' ';
          else if (is_control(c))
            fail("control character " + hex_code(c) + " in the line");
        line = trim(line);
        if (line.empty())
          continue;

        const auto        space = line.find(' ');
        const std::string word  = line.substr(0, space);
        const std::string rest  = space == std::string::npos ? "" : trim(line.substr(space + 1));
        if (word == "subsection" || word == "SUBSECTION")
          {
            if (rest.empty())
              fail("\"" + word + "\" without a subsection name");
            Section *sub = current->subsection(rest);
            if (sub == nullptr)
              fail("no subsection \"" + shown(rest) + "\" is declared " + current->where());
            open.push_back({current, n});
            current = sub;
          }
        else if (word == "end" || word == "END")
          {
            if (!rest.empty())
              fail("unexpected \"" + shown(rest) + "\" after \"" + word + "\"");
            if (open.empty())
              fail("\"" + word + "\" without an open subsection");
            current = open.back().section;
            open.pop_back();
          }
        else if (word == "set" || word == "SET")
          {
            const auto eq = rest.find('=');
            if (eq == std::string::npos)
              fail("expected \"set KEY = VALUE\", found \"" + shown(line) + "\"");
            const std::string key   = trim(rest.substr(0, eq));
            const std::string value = trim(rest.substr(eq + 1));
            Entry            *entry = current->entry(key);
            if (entry == nullptr)
              fail("no entry \"" + shown(key) + "\" is declared " + current->where());
            const auto before = set_on_line.find(entry);
            if (before != set_on_line.end())
              fail((current->parent == nullptr ? key : current->path() + "/" + key) +
                   " is set twice, on lines " + std::to_string(before->second) + " and " +
                   std::to_string(n));
            assign(*entry, value, source, n);
            set_on_line[entry] = n;
          }
        else
          fail("cannot read \"" + shown(line) +
               "\": expected \"subsection NAME\", \"set KEY = VALUE\" or \"end\"");
      }
    if (!open.empty())
      throw ParameterFileError(source, open.back().line,
                               "subsection \"" + current->path() +
                                 "\" is not closed: \"end\" is missing before the end of the "
                                 "input");
  }

  void ParameterFile::parse_file(const std::filesystem::path &file)
  {
    std::ifstream in(file);
    if (!in)
      throw ParameterFileError(file.string(), 0, "cannot be read");
    parse(in, file.string());
    if (in.bad())
      throw ParameterFileError(file.string(), 0, "read error");
  }

  namespace
  {
    // The .prm text of a JSON tree (ParameterFile::parse_json).
    void json_to_prm(const nlohmann::json &node, const int depth, std::ostream &out,
                     const std::string &source)
    {
      const auto scalar_text = [](const nlohmann::json &v) -> std::string {
        if (v.is_string())
          return v.get<std::string>();
        if (v.is_array())
          {
            std::string joined;
            for (const auto &item : v)
              joined += (joined.empty() ? "" : ", ") +
                        (item.is_string() ? item.get<std::string>() : item.dump());
            return joined;
          }
        return v.dump();
      };
      // A JSON string may hold what the .prm text cannot: a newline would start a new entry or
      // subsection, '#' a comment. Refused here, naming the key, before any text is made.
      const auto plain = [&](const std::string &key, const std::string &text, const char *what) {
        if (text.size() > ParameterFile::max_value_length)
          throw ParameterFileError(source, 0, value_too_long("\"" + shown(key) + "\"", text.size(), what));
        for (const char c : text)
          if (is_control(c))
            throw ParameterFileError(source, 0, msg("\"", shown(key), "\": the ", what,
                                                    " contains the control character ", hex_code(c)));
        if (text.find('#') != std::string::npos)
          throw ParameterFileError(source, 0, msg("\"", shown(key), "\": the ", what, " \"", shown(text),
                                                  "\" contains '#', which starts a comment in a "
                                                  "parameter file"));
        return text;
      };
      const std::string indent(2 * depth, ' ');
      for (const auto &[key, value] : node.items())
        {
          plain(key, key, "key");
          const bool is_entry =
            !value.is_object() || (value.contains("value") && !value["value"].is_object());
          if (is_entry)
            out << indent << "set " << key << " = "
                << plain(key, scalar_text(value.is_object() ? value["value"] : value), "value") << "\n";
          else
            {
              out << indent << "subsection " << key << "\n";
              json_to_prm(value, depth + 1, out, source);
              out << indent << "end\n";
            }
        }
    }
  } // namespace

  void ParameterFile::parse_json(const nlohmann::json &tree, const std::string &source)
  {
    std::ostringstream text;
    json_to_prm(tree, 0, text, source);
    std::istringstream in(text.str());
    parse(in, source);
  }

  std::vector<std::pair<std::string, std::string>> parameter_values(const std::string &prm_text)
  {
    std::istringstream                               in(prm_text);
    std::vector<std::string>                         path;
    std::vector<std::pair<std::string, std::string>> values;
    for (std::string line; std::getline(in, line);)
      {
        const auto b = line.find_first_not_of(" \t");
        if (b == std::string::npos || line[b] == '#')
          continue;
        line = line.substr(b);
        if (line.rfind("subsection ", 0) == 0)
          path.push_back(line.substr(11));
        else if (line == "end" && !path.empty())
          path.pop_back();
        else if (line.rfind("set ", 0) == 0)
          {
            std::string section;
            for (const auto &p : path)
              section += p + "/";
            const auto eq  = line.find('=');
            auto       key = line.substr(4, eq - 4);
            key.erase(key.find_last_not_of(' ') + 1);
            auto       value = line.substr(eq + 1);
            const auto vb    = value.find_first_not_of(' ');
            value            = vb == std::string::npos ? "" : value.substr(vb);
            const auto hash  = value.find(" #");
            if (hash != std::string::npos)
              value = value.substr(0, hash);
            values.emplace_back(section + key, value);
          }
      }
    return values;
  }

  const ParameterFile::Entry *ParameterFile::find(const std::string &section,
                                                  const std::string &key) const
  {
    return find_entry(section, key);
  }

  ParameterFile::Entry *ParameterFile::find_entry(const std::string &section,
                                                  const std::string &key) const
  {
    const Section *s = root.get();
    if (!section.empty())
      {
        std::stringstream parts(section);
        for (std::string part; s != nullptr && std::getline(parts, part, '/');)
          s = s->subsection(part);
      }
    return s == nullptr ? nullptr : s->entry(key);
  }

  void ParameterFile::set(const std::string &section, const std::string &key,
                          const std::string &value)
  {
    Entry *entry = find_entry(section, key);
    if (entry == nullptr)
      throw ParameterFileError("", 0,
                               "no entry \"" + shown(key) + "\" is declared " +
                                 (section.empty() ? std::string("at the top level") :
                                                    "in subsection \"" + shown(section) + "\""));
    assign(*entry, value, "", 0);
  }

  namespace
  {
    template <typename T>
    std::vector<const T *> in_order(const std::vector<std::unique_ptr<T>> &items,
                                    const ParameterFile::Order order,
                                    const std::function<const std::string &(const T &)> &name)
    {
      std::vector<const T *> out;
      for (const auto &item : items)
        out.push_back(item.get());
      if (order == ParameterFile::Order::alphabetical)
        std::stable_sort(out.begin(), out.end(), [&](const T *a, const T *b) {
          return sort_key(name(*a)) < sort_key(name(*b));
        });
      return out;
    }
  } // namespace

  std::string ParameterFile::markdown() const
  {
    const auto escape = [](const std::string &text) {
      std::string r;
      for (const char c : text)
        r += (c == '|') ? std::string("\\|") : std::string(1, c);
      return r;
    };
    std::ostringstream md;
    std::string        last_section;
    for (const Entry *e : declared)
      {
        if (e->section() != last_section)
          {
            md << "\n## " << e->section() << "\n\n";
            for (const auto &[section, help] : section_help)
              if (section == e->section())
                md << help << "\n\n";
            md << "| key | default | allowed | meaning |\n|---|---|---|---|\n";
            last_section = e->section();
          }
        md << "| `" << e->key() << "` | `" << escape(e->default_text()) << "` | "
           << escape(e->pattern().description()) << " | " << escape(e->help()) << " |\n";
      }
    return md.str();
  }

  std::string ParameterFile::print(const Style style, const Order order,
                                  const std::function<bool(const Entry &)> &omit) const
  {
    const bool         documented = style == Style::documented;
    std::ostringstream out;
    if (documented)
      out << "# Listing of Parameters\n# ---------------------\n";

    const std::function<void(const Section &, unsigned int)> print_section =
      [&](const Section &section, const unsigned int level) {
        const std::string indent(2 * level, ' ');
        auto entries = in_order<Entry>(section.entries, order,
                                       [](const Entry &e) -> const std::string & { return e.name; });
        if (omit)
          entries.erase(std::remove_if(entries.begin(), entries.end(),
                                       [&](const Entry *e) { return omit(*e); }),
                        entries.end());
        std::size_t       longest_key = 0, longest_value = 0;
        for (const Entry *e : entries)
          {
            longest_key   = std::max(longest_key, e->name.size());
            longest_value = std::max(longest_value, e->value.size());
          }
        bool first = true;
        for (const Entry *e : entries)
          {
            if (documented)
              {
                if (!first)
                  out << '\n';
                first = false;
                for (const auto &line : break_into_lines(e->documentation, 78 - 2 * level - 2))
                  out << indent << "# " << line << '\n';
              }
            out << indent << "set " << e->name << std::string(longest_key - e->name.size() + 1, ' ')
                << "= " << e->value;
            if (documented && e->value != e->default_value)
              out << std::string(longest_value - e->value.size() + 1, ' ') << "# default: "
                  << e->default_value;
            out << '\n';
          }
        if (documented && !section.entries.empty() && !section.subsections.empty())
          out << "\n\n";
        const auto subsections =
          in_order<Section>(section.subsections, order,
                            [](const Section &s) -> const std::string & { return s.name; });
        for (const Section *sub : subsections)
          {
            out << indent << "subsection " << sub->name << '\n';
            print_section(*sub, level + 1);
            out << indent << "end\n";
            if (documented)
              out << (level == 0 ? "\n\n" : "\n");
          }
      };
    print_section(*root, 0);
    return out.str();
  }
} // namespace hertzgear
