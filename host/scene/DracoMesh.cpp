#include "DracoMesh.h"

#include <stdexcept>

#ifdef WAVEVCM_HAVE_DRACO
#include <draco/compression/decode.h>
#include <draco/core/decoder_buffer.h>
#endif

namespace wv {

#ifdef WAVEVCM_HAVE_DRACO

bool dracoSupported() { return true; }

DracoMesh decodeDraco(const unsigned char* data, size_t size, const std::map<int, int>& components)
{
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(data), size);
    auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
    if (!type.ok()) throw std::runtime_error("not Draco data (" + type.status().error_msg_string() + ")");
    if (type.value() != draco::TRIANGULAR_MESH) throw std::runtime_error("the Draco data is a point cloud, not a triangle mesh");
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    if (!decoded.ok()) throw std::runtime_error("Draco cannot decode it (" + decoded.status().error_msg_string() + ")");
    const draco::Mesh& mesh = *decoded.value();

    DracoMesh out;
    out.points = mesh.num_points();
    out.indices.reserve(size_t(mesh.num_faces()) * 3);
    for (draco::FaceIndex f(0); f < mesh.num_faces(); ++f)
        for (int k = 0; k < 3; ++k) out.indices.push_back(mesh.face(f)[k].value());
    for (const auto& [id, n] : components) {
        const draco::PointAttribute* a = mesh.GetAttributeByUniqueId(uint32_t(id));
        if (!a) throw std::runtime_error("the Draco data has no attribute " + std::to_string(id));
        if (a->num_components() != n)
            throw std::runtime_error("Draco attribute " + std::to_string(id) + " has " +
                                     std::to_string(int(a->num_components())) + " components, its accessor " +
                                     std::to_string(n));
        std::vector<float>& values = out.attributes[id];
        values.resize(out.points * size_t(n));
        for (draco::PointIndex p(0); p < mesh.num_points(); ++p)
            if (!a->ConvertValue<float>(a->mapped_index(p), int8_t(n), &values[size_t(p.value()) * size_t(n)]))
                throw std::runtime_error("Draco attribute " + std::to_string(id) + " does not convert to floats");
    }
    return out;
}

#else

bool dracoSupported() { return false; }

DracoMesh decodeDraco(const unsigned char*, size_t, const std::map<int, int>&)
{
    throw std::runtime_error("this build has no Draco support: install libdraco-dev and rebuild");
}

#endif

} // namespace wv
