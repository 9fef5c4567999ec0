// Registry<Interface> (include/perideal/base/registry.h): a second plugin
// registered under a name that is taken must not silently replace the first
// (the old registry kept the later one). Registration runs before main(), so
// the error comes at the first use of the registry: every use stops with an
// Error naming the name. This program registers a second "PMB" material and
// passes only if names(), get(), all() and the library's declaration of a
// material's Model key (which lists the registry's names) each throw that
// error, while a registry without duplicates (DamageModel) still answers.

#include <perideal/damage/damage_model.h>
#include <perideal/material/material.h>

#include <iostream>
#include <string>

namespace
{
  using namespace perideal;

  class SecondPMB : public Material
  {
  public:
    static void
    declare_parameters(ParameterHandler &)
    {}
    void
    parse_parameters(ParameterHandler &, const std::string &) override
    {}
    double
    density() const override
    {
      return 1;
    }
    double
    bulk_modulus() const override
    {
      return 1;
    }
    double
    shear_modulus() const override
    {
      return 1;
    }
    void
    compute_force(const ModelState &, const std::vector<unsigned int> &) const override
    {}
    double
    stable_time_step(const ModelState &, const std::vector<unsigned int> &) const override
    {
      return 1;
    }
  };

  PERIDEAL_REGISTER(Material, SecondPMB, "PMB", "a second material named PMB (test)")

  /// 0 if @p use throws an exception whose message names the duplicate.
  template <typename Use>
  int
  expect_duplicate_error(const std::string &what, const Use &use)
  {
    try
      {
        use();
      }
    catch (const dealii::ExceptionBase &e)
      {
        const std::string message = e.get_exc_name() + std::string(" ") + e.what();
        if (message.find("two plugins are registered under the name 'PMB'") != std::string::npos)
          {
            std::cout << "PASS: " << what << " stops naming the duplicate 'PMB'\n";
            return 0;
          }
        std::cout << "FAIL: " << what << " threw, but not naming the duplicate: " << message << "\n";
        return 1;
      }
    std::cout << "FAIL: " << what << " accepted a second material named 'PMB'\n";
    return 1;
  }
} // namespace

int
main()
{
  const auto &materials = Registry<Material>::instance();
  int         failures  = 0;
  failures += expect_duplicate_error("names()", [&] { materials.names(); });
  failures += expect_duplicate_error("get()", [&] { materials.get("PMB", "test"); });
  failures += expect_duplicate_error("all()", [&] { materials.all(); });
  failures += expect_duplicate_error("Materials/NAME/Model's declaration", [] {
    ParameterHandler prm;
    declare_material_model_entry(prm);
  });
  const std::string damage = Registry<DamageModel>::instance().names(", ");
  if (damage.find("Critical stretch") == std::string::npos)
    {
      std::cout << "FAIL: the damage model registry lost its models: '" << damage << "'\n";
      ++failures;
    }
  else
    std::cout << "PASS: a registry without duplicates answers: " << damage << "\n";
  return failures == 0 ? 0 : 1;
}
