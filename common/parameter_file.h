#pragma once
// A declarative parameter set and its text form, the parameter file (.prm):
//
//   # a comment runs to the end of the line
//   subsection Gear pair
//     subsection Pinion
//       set teeth = 23
//     end
//   end
//
// Entries are declared in nested subsections, each with a pattern (the allowed values), a help
// text and a variable of the caller that receives the value: its value at declaration is the
// default. Reading a file checks every value against its pattern, converts it and assigns the
// variable; errors name the source, the line and the key. Printing gives the documented form
// (help texts as comments, `# default:` where a value differs) or a short form for hashes.
//
// A value is at most ParameterFile::max_value_length characters: a longer one is refused naming its
// key and its length before it is checked or converted, and messages quote values, keys and lines
// cut to their first characters with their length (shown(), common/errors.h).
//
// Keywords are `subsection`, `set` and `end` (or all upper case). Tabs count as spaces; a line
// ending in CR LF is read as ending in LF. Refused: a key set twice in one file, an `end` without
// an open subsection, a subsection without its `end`, a control character other than tab before
// the comment, and a line ending in a backslash (there are no continuation lines).
#include "common/errors.h"

#include <nlohmann/json_fwd.hpp>

#include <filesystem>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace hertzgear
{
  namespace patterns
  {
    // What values an entry allows; description() is the text the printed documentation and the
    // error messages show, e.g. "[Integer range 6...1000 (inclusive)]".
    class Pattern
    {
    public:
      virtual ~Pattern() = default;
      virtual bool                     match(const std::string &text) const = 0;
      virtual std::string              description() const                 = 0;
      virtual std::unique_ptr<Pattern> clone() const                       = 0;
    };

    // A pattern that copies itself as its own type (the one clone of every pattern below).
    template <typename Derived>
    class PatternOf : public Pattern
    {
    public:
      std::unique_ptr<Pattern> clone() const final
      {
        return std::make_unique<Derived>(static_cast<const Derived &>(*this));
      }
    };

    // A number in [lower, upper], white space around it allowed: an integer for Integer ("7.0" is
    // not one), a finite double read as C++ streams read it for Double ("1e6", ".5", "+3").
    template <typename T>
    class Range final : public PatternOf<Range<T>>
    {
    public:
      Range(T lower, T upper);
      bool                     match(const std::string &text) const override;
      std::string              description() const override;

    private:
      T lower, upper;
    };
    using Integer = Range<int>;
    using Double  = Range<double>;

    // Exactly "true" or "false".
    class Bool final : public PatternOf<Bool>
    {
    public:
      bool                     match(const std::string &text) const override;
      std::string              description() const override;
    };

    // One of the choices of "a|b|c", matched exactly.
    class Selection final : public PatternOf<Selection>
    {
    public:
      explicit Selection(const std::string &choices);
      bool                     match(const std::string &text) const override;
      std::string              description() const override;

    private:
      std::string choices;
    };

    // Any text.
    class Anything final : public PatternOf<Anything>
    {
    public:
      bool                     match(const std::string &text) const override;
      std::string              description() const override;
    };

    // min_length to max_length elements, each matching `element`, split at `separator` (see
    // split_list); "" is the empty list.
    class List final : public PatternOf<List>
    {
    public:
      List(const Pattern &element, unsigned int min_length, unsigned int max_length,
           const std::string &separator = ",");
      List(const List &other);
      bool                     match(const std::string &text) const override;
      std::string              description() const override;
      const Pattern           &element() const { return *element_pattern; }
      const std::string       &separator() const { return sep; }

    private:
      std::unique_ptr<Pattern> element_pattern;
      unsigned int             min_length, max_length;
      std::string              sep;
    };

    // The elements of a list value: split at each separator, spaces around an element removed;
    // trailing spaces and one trailing separator are ignored ("1, 2," is {"1", "2"}, "" is {}).
    std::vector<std::string> split_list(const std::string &text, const std::string &separator);
  } // namespace patterns

  // Bad parameter input: what() reads "<source>, line <n>: <text>" (or "<source>: <text>" when no
  // line applies, or "<text>" without a source).
  class ParameterFileError : public InputError
  {
  public:
    ParameterFileError(const std::string &source, unsigned int line, const std::string &text);
    const std::string &source() const { return source_name; }
    unsigned int       line() const { return line_number; }
    const std::string &text() const { return message; }

  private:
    std::string  source_name;
    unsigned int line_number;
    std::string  message;
  };

  class ParameterFile
  {
  public:
    class Entry
    {
    public:
      const std::string       &key() const { return name; }
      const std::string       &section() const { return section_path; } // "Gear pair/Pinion"
      const std::string       &help() const { return documentation; }
      const std::string       &default_text() const { return default_value; }
      const std::string       &text() const { return value; } // as last set
      const patterns::Pattern &pattern() const { return *allowed; }

    private:
      friend class ParameterFile;
      std::string                              name, section_path, documentation;
      std::string                              default_value, value;
      std::unique_ptr<patterns::Pattern>       allowed;
      std::function<void(const std::string &)> assign; // converts and stores into the variable
    };

    enum class Style
    {
      documented, // header, help texts as wrapped comments, "# default:" where a value differs
      short_form  // entries and subsections only (for hashes)
    };
    enum class Order
    {
      declaration,
      alphabetical // by name, subsections after entries at each level
    };

    // The longest value an entry takes, in characters: four times the longest path (4096) a file
    // entry may hold and far above the longest list (64 numbers of at most 25 characters each).
    static constexpr std::size_t max_value_length = 16384;

    ParameterFile();
    ~ParameterFile();
    ParameterFile(const ParameterFile &)            = delete;
    ParameterFile &operator=(const ParameterFile &) = delete;

    // Declaration. enter_subsection creates the subsection or re-enters it. add binds `value`
    // (which must outlive this object) and takes its current value as the default; a default the
    // pattern refuses, an empty help text or a key declared twice is a programming error
    // (std::logic_error).
    // A subsection's help text, when given, documents it in markdown().
    void         enter_subsection(const std::string &name, const std::string &help = "");
    void         leave_subsection();
    const Entry &add(const std::string &key, int &value, const patterns::Pattern &pattern,
                     const std::string &help);
    const Entry &add(const std::string &key, double &value, const patterns::Pattern &pattern,
                     const std::string &help);
    const Entry &add(const std::string &key, bool &value, const patterns::Pattern &pattern,
                     const std::string &help);
    const Entry &add(const std::string &key, std::string &value, const patterns::Pattern &pattern,
                     const std::string &help);
    // The pattern must be a patterns::List of patterns::Double elements.
    const Entry &add(const std::string &key, std::vector<double> &value,
                     const patterns::Pattern &pattern, const std::string &help);

    // Reads parameter-file text; `source` names it in messages. Throws ParameterFileError.
    void parse(std::istream &in, const std::string &source);
    // Reads a file; messages name it as given.
    void parse_file(const std::filesystem::path &file);
    // Reads a JSON tree as the same tree of a .prm file: objects are subsections, scalars (or
    // {"value": ...} objects) are entries, arrays are comma lists; it is read as .prm text, so
    // both formats share one parser and one set of checks.
    void parse_json(const nlohmann::json &tree, const std::string &source);

    // The entry `key` of subsection `section` ("Gear pair/Pinion", "" for the top level), or null.
    const Entry *find(const std::string &section, const std::string &key) const;
    // Sets one entry from text (kept as given, checked and converted as in a file). Throws
    // ParameterFileError (without a source) for an unknown entry or a value it refuses.
    void set(const std::string &section, const std::string &key, const std::string &value);

    // `omit`, when given, leaves out the entries it holds for (the width of the columns is that of
    // the entries printed): a hash that ignores entries at a value that means "absent".
    std::string print(Style style, Order order = Order::declaration,
                      const std::function<bool(const Entry &)> &omit = {}) const;
    // The reference of every entry as Markdown, in declaration order: a "## Section/Sub" heading
    // with the subsection's help texts wherever the section changes, then a table of key,
    // default, allowed values and meaning ('|' escaped).
    std::string markdown() const;

  private:
    struct Section;
    Entry &declare(const std::string &key, const patterns::Pattern &pattern,
                   const std::string &help, const std::string &default_value,
                   std::function<void(const std::string &)> assign);
    Entry *find_entry(const std::string &section, const std::string &key) const;
    void   assign(Entry &entry, const std::string &value, const std::string &source,
                  unsigned int line);

    std::unique_ptr<Section> root;
    std::vector<Section *>   path; // declaration: the open subsections
    std::vector<const Entry *> declared; // every entry, in declaration order
    std::vector<std::pair<std::string, std::string>> section_help; // (section path, help)
  };

  // ("Section/Sub/key", value) of every `set` line of .prm text, in order (the used parameters of a
  // run read back).
  std::vector<std::pair<std::string, std::string>> parameter_values(const std::string &prm_text);
} // namespace hertzgear
