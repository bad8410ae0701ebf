#include "volguide/render/exr_layers.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>

#include <fstream>

#include "volguide/core/atomic_write.h"
#include "volguide/core/error.h"
#include "volguide/render/exr_header_check.h"

namespace volguide {

void write_exr_layers(const std::string& path, const ExrLayers& layers) {
    const size_t n = size_t(layers.width) * size_t(layers.height);
    if (layers.width <= 0 || layers.height <= 0) fail_file(path, "cannot write an empty image");
    for (const auto& [name, values] : layers.channels)
        if (values.size() != n) fail_file(path, "channel " + name + " does not match the image size");
    const std::string error = write_atomically(path, [&](const std::string& tmp) {
        Imf::Header header(layers.width, layers.height);
        for (const auto& [name, value] : layers.attributes) header.insert(name, Imf::StringAttribute(value));
        Imf::FrameBuffer fb;
        for (const auto& [name, values] : layers.channels) {
            header.channels().insert(name, Imf::Channel(Imf::FLOAT));
            char* base = const_cast<char*>(reinterpret_cast<const char*>(values.data()));
            fb.insert(name, Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * size_t(layers.width)));
        }
        Imf::OutputFile file(tmp.c_str(), header);
        file.setFrameBuffer(fb);
        file.writePixels(layers.height);
    });
    if (!error.empty()) fail_file(path, "cannot write image: " + error);
}

ExrLayers read_exr_layers(const std::string& path) {
    if (!std::ifstream(path, std::ios::binary)) fail_file(path, "cannot open image file");
    check_exr_header(path);
    try {
        Imf::InputFile file(path.c_str());
        const Imf::Header& header = file.header();
        const Imath::Box2i dw = header.dataWindow();
        ExrLayers layers;
        size_t channel_count = 0;  // OpenEXR's channel iterators are not standard iterators
        for (auto it = header.channels().begin(); it != header.channels().end(); ++it) ++channel_count;
        const ExrSize size = checked_exr_size(path, dw.min.x, dw.min.y, dw.max.x, dw.max.y, channel_count);
        layers.width = size.width;
        layers.height = size.height;
        const size_t n = size_t(layers.width) * size_t(layers.height);
        for (auto it = header.begin(); it != header.end(); ++it)
            if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
                layers.attributes[it.name()] = s->value();
        Imf::FrameBuffer fb;
        for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
            std::vector<float>& values = layers.channels[it.name()];
            values.assign(n, 0.f);
            // The data window may not start at (0, 0): offset the base pointer (OpenEXR's convention).
            char* base = reinterpret_cast<char*>(values.data()) -
                         (ptrdiff_t(dw.min.x) + ptrdiff_t(dw.min.y) * layers.width) * ptrdiff_t(sizeof(float));
            fb.insert(it.name(), Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * size_t(layers.width)));
        }
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
        return layers;
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        fail_file(path, std::string("cannot read EXR image: ") + e.what());
    }
}

}  // namespace volguide
