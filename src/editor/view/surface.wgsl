// The surface shader of Pappus (see `surface.rs`): a light that travels with the camera, and
// nothing else. Front faces take the material's colour (or the mesh's vertex colours while a
// quantity is shown), modulated by a checkerboard when the mesh has UVs; back faces, seen
// through a hole or on a wrongly oriented face, are tinted blue-grey so a flipped or open
// surface is visible at a glance.

#import bevy_pbr::{
    forward_io::VertexOutput,
    mesh_view_bindings::view,
}

struct SurfaceMaterial {
    color: vec4<f32>,
    back_color: vec4<f32>,
}

@group(#{MATERIAL_BIND_GROUP}) @binding(0) var<uniform> material: SurfaceMaterial;

@fragment
fn fragment(in: VertexOutput, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var base = material.color.rgb;
#ifdef VERTEX_COLORS
    base = in.color.rgb;
#endif
#ifdef VERTEX_UVS_A
    // The checkerboard of a UV layout (16 x 16 squares over [0, 1]^2): squares that stay square
    // on the surface are conformal, squares of one size area-preserving. Two soft tones.
    let cell = floor(in.uv * 16.0);
    let odd = (i32(cell.x) + i32(cell.y)) & 1;
    base = base * select(1.0, 0.62, odd == 1);
#endif
    if !front {
        base = material.back_color.rgb;
    }
    let to_eye = normalize(view.world_position - in.world_position.xyz);
#ifdef VERTEX_NORMALS
    var n = normalize(in.world_normal);
#else
    // Flat shading: the face's normal, from how the position changes across the pixel.
    var n = normalize(cross(dpdx(in.world_position.xyz), dpdy(in.world_position.xyz)));
#endif
    if dot(n, to_eye) < 0.0 {
        n = -n;
    }
    // A key light above and left of the eye, and a weaker one at the eye, so creases read
    // whichever way the surface faces the camera.
    let up = view.world_from_view[1].xyz;
    let right = view.world_from_view[0].xyz;
    let key = normalize(to_eye + 0.6 * up - 0.4 * right);
    let shade = 0.22 + 0.58 * max(dot(n, key), 0.0) + 0.2 * dot(n, to_eye);
    return vec4<f32>(base * shade, 1.0);
}
