// The Solve request the service tests, the soak and the service benchmark send: one view of a
// floor (y = 0) from `eye` looking at (0, 0.5, -2), one point light, the room's bounds.
#pragma once

#include <lixel/service/proto_convert.h>
#include <lixel/solver/camera.h>
#include <lixel/v1/lixel.pb.h>

#include <string>

namespace lixel::testing {

inline v1::SolveRequest FloorSolve(int side, const Vec3& eye, const Vec3& light,
                                   const std::string& plane_name = "") {
    v1::SolveRequest request;
    v1::Camera* camera = request.add_views();
    service::EncodeMat4(
        Perspective(1.0, 1.0, 0.1, 100.0) * LookAt(eye, Vec3(0, 0.5, -2), Vec3::UnitY()),
        camera->mutable_viewer());
    camera->set_width(side);
    camera->set_height(side);
    v1::PlaneOfInterest* floor = request.add_planes();
    if (!plane_name.empty()) floor->set_name(plane_name);
    floor->mutable_plane()->set_y(1.0);
    service::EncodeVec4(Vec4(light.x(), light.y(), light.z(), 1.0),
                        request.add_lights()->mutable_position());
    service::EncodeVec3(Vec3(-10, 0, -5), request.mutable_bounds()->mutable_min());
    service::EncodeVec3(Vec3(10, 8, 10), request.mutable_bounds()->mutable_max());
    return request;
}

}  // namespace lixel::testing
