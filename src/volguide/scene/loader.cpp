#include "volguide/scene/loader.h"

#include <exception>
#include <vector>

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
        objects_[size_t(index)] = obj;
        state_[size_t(index)] = kDone;
        return obj;
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
