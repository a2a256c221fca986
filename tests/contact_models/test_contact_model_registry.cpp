// The contact model registry (library): the built-in types and their parameters, a configuration
// without a type named by its key, and a custom factory that build() uses, that rejects unknown keys
// before it runs and that replaces an earlier one of the same type.
#include <memory>
#include <nlohmann/json.hpp>

#include "common/input_error.hpp"
#include "contact_models/coulomb_model.hpp"
#include "contact_models/registry.hpp"
#include "terrain/plane.hpp"
#include "test_support.hpp"

namespace nmdp::test {
namespace {
using nlohmann::json;

TEST(ContactModelRegistryTest, BuiltinTypes) {
  const ContactModelRegistry registry = ContactModelRegistry::withBuiltins();
  EXPECT_EQ(registry.types(), (std::vector<std::string>{"coulomb", "mlp", "rbf"}));
  EXPECT_EQ(registry.parameters("coulomb"), kCoulombParameters);
  EXPECT_THROW(registry.parameters("nope"), InputError);
}

TEST(ContactModelRegistryTest, MissingTypeNamesTheKey) {
  const ContactModelRegistry registry = ContactModelRegistry::withBuiltins();
  const ConfigContext ctx{"scene.json: contacts.model", ""};
  for (const json& config : {json{{"mu", 0.5}}, json::object(), json{{"type", 3}}}) {
    SCOPED_TRACE(config.dump());
    try {
      registry.build(config, ctx);
      ADD_FAILURE() << "build accepted a configuration without a type";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("scene.json: contacts.model.type"), std::string::npos) << m;
      EXPECT_NE(m.find("missing"), std::string::npos) << m;
      EXPECT_NE(m.find("coulomb, mlp, rbf"), std::string::npos) << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
  }
  EXPECT_THROW(registry.build(json::array(), ctx), InputError);
}

// A model that returns a constant force, to check that add() is used by build().
class ConstantModel : public ContactModel {
 public:
  ConstantModel(double force, int K) : force_(force), K_(K) {}
  int vertexCount() const override { return K_; }
  DerivativeSupport derivative() const override { return DerivativeSupport::None; }
  std::string describe() const override { return "constant " + std::to_string(force_); }
  void evaluate(const std::vector<ContactFrame>& frames, const Terrain&, std::vector<ContactWrenches>& out,
                bool) const override {
    for (size_t i = 0; i < frames.size(); ++i) {
      out[i].resize(K_);
      out[i].V.row(5).setConstant(force_);
    }
  }
  double force() const { return force_; }

 private:
  double force_;
  int K_;
};

TEST(ContactModelRegistryTest, CustomFactoryIsUsed) {
  ContactModelRegistry registry = ContactModelRegistry::withBuiltins();
  int calls = 0;
  json seen;
  registry.add("constant", {"force", "K"}, [&](const json& params, const ConfigContext& ctx) -> std::unique_ptr<ContactModel> {
    ++calls;
    seen = params;
    return std::make_unique<ConstantModel>(readNumber(params, "force", 1.0, ctx), readInteger(params, "K", 3, ctx, 1, 100));
  });
  EXPECT_EQ(registry.types(), (std::vector<std::string>{"constant", "coulomb", "mlp", "rbf"}));
  EXPECT_EQ(registry.parameters("constant"), (std::vector<std::string>{"force", "K"}));

  const std::unique_ptr<ContactModel> model = registry.build({{"type", "constant"}, {"force", 12.5}, {"K", 4}}, {"test", ""});
  EXPECT_EQ(calls, 1);
  EXPECT_FALSE(seen.contains("type")) << "the factory gets the parameters without \"type\": " << seen.dump();
  const auto* constant = dynamic_cast<const ConstantModel*>(model.get());
  ASSERT_NE(constant, nullptr) << model->describe();
  EXPECT_EQ(constant->force(), 12.5);
  EXPECT_EQ(model->vertexCount(), 4);
  std::vector<ContactWrenches> out(1);
  model->evaluate({ContactFrame{}}, PlaneTerrain(), out, false);
  EXPECT_EQ(out[0].V(5, 3), 12.5);

  // An unknown key is rejected before the factory runs, naming the key and the closest valid one.
  try {
    registry.build({{"type", "constant"}, {"forse", 1.0}}, {"test", ""});
    ADD_FAILURE() << "unknown key accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("test.forse"), std::string::npos) << m;
    EXPECT_NE(m.find("'force'"), std::string::npos) << m;
  }
  EXPECT_EQ(calls, 1);

  // Adding a type again replaces its factory; the built-ins still work.
  registry.add("constant", {}, [](const json&, const ConfigContext&) -> std::unique_ptr<ContactModel> {
    return std::make_unique<ConstantModel>(-1.0, 3);
  });
  const std::unique_ptr<ContactModel> replaced = registry.build({{"type", "constant"}}, {"test", ""});
  EXPECT_EQ(dynamic_cast<const ConstantModel&>(*replaced).force(), -1.0);
  EXPECT_EQ(registry.build({{"type", "coulomb"}}, {"test", ""})->vertexCount(), 6);
  // The unknown-type message now lists the custom type too.
  try {
    registry.build({{"type", "constnt"}}, {"test", ""});
    ADD_FAILURE() << "unknown type accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("did you mean 'constant'"), std::string::npos) << m;
    EXPECT_NE(m.find("constant, coulomb, mlp, rbf"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace nmdp::test
