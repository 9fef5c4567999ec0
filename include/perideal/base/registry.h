#pragma once
// One registry per extension point (materials, damage models, time
// integrators, ...): each plugin file registers its class at its bottom with
// PERIDEAL_REGISTER(Interface, Class, "Name", "documentation"); the valid
// names (Patterns::Selection), the parameter documentation and the factory
// all come from here, so adding a plugin touches no core file.
//
// Registration runs during static initialisation, where an exception cannot
// be reported: a name registered twice is remembered and reported by every
// later use of the registry (an Error naming the name and both documentations).

#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>

#include <functional>
#include <iterator>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace perideal
{
  template <class Interface>
  class Registry
  {
  public:
    struct Entry
    {
      std::string                                          name;
      std::string                                          documentation;
      std::function<void(dealii::ParameterHandler &)>      declare;
      std::function<std::unique_ptr<Interface>()>          create;
    };

    static Registry &
    instance()
    {
      static Registry registry;
      return registry;
    }

    /// Adds @p entry; a second entry of the same name is an error at the next use.
    bool
    add(const Entry &entry)
    {
      if (!entries.emplace(entry.name, entry).second)
        duplicates.push_back(entry);
      return true;
    }

    /// The entry @p name; @p where names the key in the error if there is none.
    const Entry &
    get(const std::string &name, const std::string &where) const
    {
      check();
      const auto it = entries.find(name);
      AssertThrow(it != entries.end(),
                  dealii::ExcMessage(where + ": unknown model '" + name + "'; valid names are: " + names(", ")));
      return it->second;
    }

    std::unique_ptr<Interface>
    create(const std::string &name, const std::string &where) const
    {
      return get(name, where).create();
    }

    std::string
    names(const std::string &separator = "|") const
    {
      check();
      std::string s;
      for (const auto &e : entries)
        s += (s.empty() ? "" : separator) + e.first;
      return s;
    }

    /// "A: doc of A. B, C: doc of B and C." for the documentation of a key
    /// that selects a model; consecutive names of one documentation share it.
    std::string
    documentation() const
    {
      check();
      std::string s;
      for (auto it = entries.begin(); it != entries.end(); ++it)
        {
          s += (s.empty() ? "" : (std::prev(it)->second.documentation == it->second.documentation ? ", " : " ")) +
               it->first;
          const auto next = std::next(it);
          if (next == entries.end() || next->second.documentation != it->second.documentation)
            s += ": " + it->second.documentation;
        }
      return s;
    }

    /// The pattern of a key that names one of the registered models.
    dealii::Patterns::Selection
    selection() const
    {
      return dealii::Patterns::Selection(names("|"));
    }

    const std::map<std::string, Entry> &
    all() const
    {
      check();
      return entries;
    }

  private:
    void
    check() const
    {
      if (duplicates.empty())
        return;
      const Entry &d = duplicates.front();
      AssertThrow(false,
                  dealii::ExcMessage("two plugins are registered under the name '" + d.name + "' (\"" +
                                     entries.at(d.name).documentation.substr(0, 60) + "...\" and \"" +
                                     d.documentation.substr(0, 60) +
                                     "...\"): names of one extension point must be unique; rename one"));
    }

    std::map<std::string, Entry> entries;
    std::vector<Entry>           duplicates;
  };
} // namespace perideal

/// Registers @p Class (with a static declare_parameters(ParameterHandler &)
/// and a default constructor) as @p name of the extension point @p Interface.
#define PERIDEAL_REGISTER(Interface, Class, name, doc)                           \
  namespace                                                                      \
  {                                                                              \
    const bool registered_##Class = ::perideal::Registry<Interface>::instance()  \
      .add({name, doc, &Class::declare_parameters, []() {                        \
              return std::unique_ptr<Interface>(new Class());                    \
            }});                                                                 \
  }
