#include "penumbra/scene/object_parser.h"

#include "penumbra/scene/shape_parser.h"
#include "penumbra/scene/transform_parser.h"

namespace penumbra {

using nlohmann::json;

bool is_instance_entry(const json& v) {
  if (!v.is_object()) return false;
  const json* type = json_find(v, "type");
  return type && type->is_string() && type->get<std::string>() == "instance";
}

std::vector<ObjectDesc> parse_objects(const json& v, const JsonPlace& place,
                                      const std::set<std::string>& materials,
                                      const std::string& base_dir,
                                      std::vector<std::string>& warnings) {
  if (!v.is_object()) place.fail("expected an object mapping object names to objects");
  std::vector<ObjectDesc> out;
  for (const auto& [name, object] : v.items()) {
    const JsonPlace at = place.key(name);
    if (name.empty()) at.fail("object name must not be empty");
    if (!object.is_object()) at.fail("expected an object with \"shapes\"");
    json_check_keys(object, at, {"shapes"}, "an object");
    ObjectDesc desc;
    desc.name = name;
    desc.path = at.path;
    const JsonPlace sp = at.key("shapes");
    const json& shapes = json_array(json_require(object, at, "shapes"), sp);
    if (shapes.empty()) sp.fail("an object needs at least one shape");
    for (size_t i = 0; i < shapes.size(); ++i) {
      const JsonPlace shape_at = sp.index(i);
      // What the two-level structure does not support, refused by name.
      if (is_instance_entry(shapes[i]))
        shape_at.fail("instances inside objects (nested instancing) are not supported");
      if (shapes[i].is_object() && json_find(shapes[i], "transform_end"))
        shape_at.key("transform_end").fail("shapes of an object cannot move (transform_end)");
      ShapeDesc shape = parse_shape(shapes[i], shape_at, materials, base_dir, warnings);
      if (shape.emission)
        shape_at.key("emission")
            .fail(
                "shapes of an object cannot be emissive: area lights in instances are not "
                "supported (as in pbrt-v4); make the emitter an ordinary shape");
      desc.shapes.push_back(std::move(shape));
    }
    out.push_back(std::move(desc));
  }
  return out;
}

InstanceDesc parse_instance(const json& v, const JsonPlace& place,
                            const std::vector<ObjectDesc>& objects) {
  if (json_find(v, "transform_end"))
    place.key("transform_end").fail("instances cannot move (transform_end is not supported)");
  json_check_keys(v, place, {"type", "name", "object", "transform"}, "an instance");
  InstanceDesc inst;
  inst.path = place.path;
  if (const json* name = json_find(v, "name")) inst.name = json_string(*name, place.key("name"));
  const JsonPlace op = place.key("object");
  const std::string object = json_string(json_require(v, place, "object"), op);
  bool found = false;
  for (size_t i = 0; i < objects.size() && !found; ++i)
    if (objects[i].name == object) inst.object = static_cast<uint32_t>(i), found = true;
  if (!found) {
    std::string list;
    for (const ObjectDesc& o : objects) list += (list.empty() ? "" : ", ") + o.name;
    op.fail("unknown object \"" + object + "\"" +
            (list.empty() ? " (no objects are defined)" : " (defined: " + list + ")"));
  }
  if (const json* ops = json_find(v, "transform"))
    inst.to_world = parse_transform(*ops, place.key("transform"));
  return inst;
}

}  // namespace penumbra
