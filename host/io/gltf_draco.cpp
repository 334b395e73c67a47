// Primitives compressed with KHR_draco_mesh_compression, decoded with Debian's libdraco into the
// attribute arrays their accessors describe (the accessors of such a primitive have no buffer view:
// their type, component type and count say what the Draco data decodes to).

#include <draco/compression/decode.h>

#include <cstring>

#include "io/gltf_accessors.h"
#include "io/gltf_contents.h"

namespace harmonia::detail {
namespace {

template <typename T>
bool convert_all(const draco::PointAttribute& attribute, const draco::Mesh& mesh,
                 AccessorData& data) {
  std::vector<T> element(static_cast<std::size_t>(data.components()));
  for (std::int64_t point = 0; point < data.count; ++point) {
    const draco::AttributeValueIndex value =
        attribute.mapped_index(draco::PointIndex(static_cast<std::uint32_t>(point)));
    if (!attribute.ConvertValue<T>(value, static_cast<std::int8_t>(element.size()),
                                   element.data())) {
      return false;
    }
    for (int component = 0; component < data.components(); ++component) {
      std::memcpy(data.data.data() + point * data.element_size + data.component_offset(component),
                  &element[static_cast<std::size_t>(component)], sizeof(T));
    }
  }
  (void)mesh;
  return true;
}

bool convert_attribute(const draco::PointAttribute& attribute, const draco::Mesh& mesh,
                       AccessorData& data) {
  switch (data.component_type) {
    case kByte: return convert_all<std::int8_t>(attribute, mesh, data);
    case kUnsignedByte: return convert_all<std::uint8_t>(attribute, mesh, data);
    case kShort: return convert_all<std::int16_t>(attribute, mesh, data);
    case kUnsignedShort: return convert_all<std::uint16_t>(attribute, mesh, data);
    case kUnsignedInt: return convert_all<std::uint32_t>(attribute, mesh, data);
    case kFloat: return convert_all<float>(attribute, mesh, data);
    default: return false;
  }
}

DracoPrimitive decode_one(const GltfContents& contents, const nlohmann::json& primitive,
                          const nlohmann::json& draco_object, const std::string& path) {
  const std::string ext_path = path + ".extensions.KHR_draco_mesh_compression";
  if (!draco_object.is_object()) contents.refuse(ext_path, "must be an object");
  const std::int64_t view = index_member(contents, draco_object, "bufferView", ext_path);
  if (view < 0) contents.refuse(ext_path, "needs a bufferView");
  const std::span<const std::uint8_t> bytes =
      contents.view_bytes(static_cast<int>(view), ext_path + ".bufferView");
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok() || !decoded.value()) {
    contents.refuse(ext_path, "Draco cannot decode it: " +
                                  (decoded.ok() ? std::string("no mesh") : decoded.status().error_msg_string()));
  }
  const std::unique_ptr<draco::Mesh> mesh = std::move(decoded).value();
  DracoPrimitive out;
  out.indices.reserve(static_cast<std::size_t>(mesh->num_faces()) * 3);
  for (draco::FaceIndex face(0); face < mesh->num_faces(); ++face) {
    for (int corner = 0; corner < 3; ++corner) out.indices.push_back(mesh->face(face)[corner].value());
  }
  const auto attributes = draco_object.find("attributes");
  if (attributes == draco_object.end() || !attributes->is_object()) {
    contents.refuse(ext_path, "needs an attributes object");
  }
  const auto primitive_attributes = primitive.find("attributes");
  for (const auto& [name, id] : attributes->items()) {
    const std::string attribute_path = ext_path + ".attributes." + name;
    if (!id.is_number_integer() || id.get<std::int64_t>() < 0) {
      contents.refuse(attribute_path, "must be a Draco attribute id");
    }
    if (primitive_attributes == primitive.end() || !primitive_attributes->contains(name)) {
      contents.refuse(attribute_path, "the primitive has no accessor for it");
    }
    const std::int64_t accessor_index =
        index_member(contents, *primitive_attributes, name, path + ".attributes");
    const nlohmann::json& accessor = element(contents, "accessors", accessor_index, attribute_path);
    const draco::PointAttribute* attribute =
        mesh->GetAttributeByUniqueId(static_cast<std::uint32_t>(id.get<std::int64_t>()));
    if (attribute == nullptr) contents.refuse(attribute_path, "the Draco data has no such attribute");
    // The accessor says what the data decodes to; read it as if it had zeros, then fill it.
    nlohmann::json plain = accessor;
    plain.erase("bufferView");
    plain.erase("sparse");
    plain["count"] = mesh->num_points();
    GltfContents shape;
    shape.name = contents.name;
    shape.input_bytes = contents.input_bytes;
    shape.json = {{"accessors", nlohmann::json::array({plain})}};
    auto data = std::make_shared<AccessorData>(read_accessor(shape, 0, attribute_path));
    if (index_member(contents, accessor, "count", attribute_path) != static_cast<std::int64_t>(mesh->num_points())) {
      contents.refuse(attribute_path, "accessor " + std::to_string(accessor_index) + " has count " +
                                          std::to_string(index_member(contents, accessor, "count", attribute_path)) +
                                          ", the Draco data " + std::to_string(mesh->num_points()) +
                                          " points");
    }
    if (attribute->num_components() != data->components() ||
        !convert_attribute(*attribute, *mesh, *data)) {
      contents.refuse(attribute_path, "the Draco attribute does not convert to accessor " +
                                          std::to_string(accessor_index) + "'s type");
    }
    out.attributes[name] = std::move(data);
  }
  return out;
}

}  // namespace

void decode_draco_primitives(GltfContents& contents) {
  const nlohmann::json& meshes = top_array(contents, "meshes");
  for (std::size_t mesh = 0; mesh < meshes.size(); ++mesh) {
    if (!meshes[mesh].is_object()) continue;
    const auto primitives = meshes[mesh].find("primitives");
    if (primitives == meshes[mesh].end() || !primitives->is_array()) continue;
    for (std::size_t index = 0; index < primitives->size(); ++index) {
      const nlohmann::json& primitive = (*primitives)[index];
      if (!primitive.is_object()) continue;
      const auto extensions = primitive.find("extensions");
      if (extensions == primitive.end() || !extensions->is_object()) continue;
      const auto draco = extensions->find("KHR_draco_mesh_compression");
      if (draco == extensions->end()) continue;
      const std::string path =
          "meshes[" + std::to_string(mesh) + "].primitives[" + std::to_string(index) + "]";
      contents.decoded_draco[{static_cast<int>(mesh), static_cast<int>(index)}] =
          decode_one(contents, primitive, *draco, path);
    }
  }
}

}  // namespace harmonia::detail
