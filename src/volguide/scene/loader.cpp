#include "volguide/scene/loader.h"

#include <exception>
#include <vector>

#include "volguide/geometry/shape.h"
#include "volguide/scene/scene_graph.h"
#include "volguide/scene/xml_reader.h"

namespace volguide {

namespace {

// Creates objects depth-first (children before parents); objects with an id are created once
// and shared by every reference.
class Instantiator {
  public:
    Instantiator(SceneGraph& graph, const ObjectFactory& factory)
        : graph_(graph), factory_(factory), objects_(graph.nodes.size()), state_(graph.nodes.size(), kNew) {}

    Properties root() {
        fill_children(0);
        return std::move(graph_.nodes[0].props);
    }

  private:
    enum State { kNew, kBusy, kDone };

    void fill_children(int index) {
        // Copy: instantiating children may not touch this node, but keep the loop independent
        // of the vector anyway.
        std::vector<SceneGraph::Child> children = graph_.nodes[size_t(index)].children;
        for (const SceneGraph::Child& c : children) {
            int target = c.node;
            if (target < 0) {
                auto it = graph_.ids.find(c.ref_id);
                if (it == graph_.ids.end()) fail(c.loc, "<ref>: no object has id \"{}\"", c.ref_id);
                target = it->second;
                if (target == 0) fail(c.loc, "<ref>: \"{}\" is the scene itself", c.ref_id);
            }
            check_mesh_attribute_user(index, target, c.loc);
            ObjectPtr obj = instantiate(target, c.loc);
            graph_.nodes[size_t(index)].props.set(c.name, graph_.nodes[size_t(target)].tag, obj, c.loc);
        }
    }

    ObjectPtr instantiate(int index, const SourceLocation& used_at) {
        if (state_[size_t(index)] == kDone) return objects_[size_t(index)];
        if (state_[size_t(index)] == kBusy)
            fail(used_at, "reference cycle: object \"{}\" contains itself",
                 graph_.nodes[size_t(index)].props.id());
        state_[size_t(index)] = kBusy;
        fill_children(index);
        SceneGraph::Node& node = graph_.nodes[size_t(index)];
        ObjectPtr obj;
        try {
            obj = factory_(node.tag, node.props);
        } catch (const InputError&) {
            throw;
        } catch (const std::exception& e) {  // give plugin failures a location too
            node.props.fail_here("could not create {} '{}': {}", node.tag, node.props.type(), e.what());
        }
        if (!obj) node.props.fail_here("{} '{}' could not be created", node.tag, node.props.type());
        node.props.check_all_used();
        if (node.tag == "shape") check_mesh_attributes(index, *obj);
        objects_[size_t(index)] = obj;
        state_[size_t(index)] = kDone;
        return obj;
    }

    // Only BSDFs (of a shape) can use a mesh_attribute texture; see check_mesh_attributes.
    void check_mesh_attribute_user(int parent, int child, const SourceLocation& loc) const {
        const SceneGraph::Node& c = graph_.nodes[size_t(child)];
        const std::string& parent_tag = graph_.nodes[size_t(parent)].tag;
        if (c.tag == "texture" && c.props.type() == "mesh_attribute" && parent_tag != "bsdf" && parent_tag != "scene")
            fail(loc, "mesh_attribute textures can only be used by BSDFs (of a mesh), not by a {}", parent_tag);
    }

    int target_of(const SceneGraph::Child& c) const {
        if (c.node >= 0) return c.node;
        auto it = graph_.ids.find(c.ref_id);
        return it == graph_.ids.end() ? -1 : it->second;
    }

    // A `mesh_attribute` texture reads the attribute of the shape it is evaluated on: every shape
    // whose BSDF (nested BSDFs and textures included) uses one must have that attribute, checked here
    // once the shape exists, at the texture's line. Other users of the texture are refused.
    void check_mesh_attributes(int shape_index, const Object& obj) {
        const auto* shape = dynamic_cast<const Shape*>(&obj);
        for (const SceneGraph::Child& c : graph_.nodes[size_t(shape_index)].children) {
            const int t = target_of(c);
            if (t >= 0 && graph_.nodes[size_t(t)].tag == "bsdf") check_attributes_below(t, shape, 0);
        }
    }

    void check_attributes_below(int index, const Shape* shape, int depth) {
        const SceneGraph::Node& node = graph_.nodes[size_t(index)];
        if (depth > 64) return;  // reference cycles were refused when the objects were created
        if (node.tag == "texture" && node.props.type() == "mesh_attribute") check_attribute(node, shape);
        for (const SceneGraph::Child& c : node.children) {
            const int t = target_of(c);
            if (t < 0) continue;
            const std::string& tag = graph_.nodes[size_t(t)].tag;
            if (tag == "bsdf" || tag == "texture") check_attributes_below(t, shape, depth + 1);
        }
    }

    static void check_attribute(const SceneGraph::Node& tex, const Shape* shape) {
        const Properties::Entry* e = tex.props.find("name");
        const std::string* name = e ? std::get_if<std::string>(&e->value) : nullptr;
        if (!name) return;  // the texture's factory required it
        if (!shape || shape->attribute_channels(*name) == 0)
            tex.props.fail_here("mesh_attribute: the shape using this texture ({}) has no attribute \"{}\"",
                                shape ? shape->to_string() : std::string("not a shape"), *name);
    }

    SceneGraph& graph_;
    const ObjectFactory& factory_;
    std::vector<ObjectPtr> objects_;
    std::vector<State> state_;
};

}  // namespace

Properties load_scene_properties(const std::string& path, const LoadOptions& options,
                                 const ObjectFactory& factory) {
    SceneGraph graph = read_scene_graph(path, options);
    return Instantiator(graph, factory).root();
}

Properties load_scene_properties(const std::string& path, const LoadOptions& options) {
    return load_scene_properties(path, options, create_object);
}

}  // namespace volguide
