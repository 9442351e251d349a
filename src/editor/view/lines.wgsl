// The overlay's thin lines and dots (see `overlay_lines.rs`): every segment a quad of two
// triangles, widened on screen by this vertex shader, each vertex knowing both ends of its
// segment; every dot a hexagon turned to face the camera.

#import bevy_pbr::mesh_view_bindings::view

struct OverlayLines {
    width: f32,
    depth_pull: f32,
}

@group(#{MATERIAL_BIND_GROUP}) @binding(0) var<uniform> lines: OverlayLines;

struct Vertex {
    @location(0) own_end: vec3<f32>,
    @location(1) other_end: vec3<f32>,
    // Offsets in the camera's plane (right, up): the own end's in xy, the other's in zw.
    @location(2) facing: vec4<f32>,
    // -0.5 or 0.5: the side of the segment, seen from the own end towards the other; 0 for a
    // dot's corner, placed by its offset alone.
    @location(3) side: f32,
    @location(4) color: vec4<f32>,
}

struct Fragment {
    @builtin(position) position: vec4<f32>,
    @location(0) color: vec4<f32>,
}

fn to_clip(p: vec3<f32>, offset: vec2<f32>) -> vec4<f32> {
    let right = view.world_from_view[0].xyz;
    let up = view.world_from_view[1].xyz;
    return view.clip_from_world * vec4<f32>(p + offset.x * right + offset.y * up, 1.0);
}

// `p` moved along the segment onto the near plane when it lies behind it and `q` does not
// (Bevy's depth is reversed: the near plane is z = w, and behind it z > w).
fn onto_near_plane(p: vec4<f32>, q: vec4<f32>) -> vec4<f32> {
    let behind_p = p.z - p.w;
    let behind_q = q.z - q.w;
    if behind_p > 0.0 && behind_q <= 0.0 {
        // A little past the plane, so rounding does not leave the point behind it.
        return mix(p, q, behind_p / (behind_p - behind_q) + 4.88e-4);
    }
    return p;
}

@vertex
fn vertex(v: Vertex) -> Fragment {
    let own = to_clip(v.own_end, v.facing.xy);
    let other = to_clip(v.other_end, v.facing.zw);
    if own.z > own.w && other.z > other.w {
        // Wholly behind the eye: a point outside the view, so the triangle is dropped.
        return Fragment(vec4<f32>(0.0, 0.0, 2.0, 1.0), v.color);
    }
    let at = onto_near_plane(own, other);
    let to = onto_near_plane(other, own);
    // In pixels from the middle of the viewport.
    let half_size = 0.5 * view.viewport.zw;
    let at_px = half_size * at.xy / at.w;
    let to_px = half_size * to.xy / to.w;
    var along = vec2<f32>(1.0, 0.0);
    if distance(at_px, to_px) > 1e-6 {
        along = normalize(to_px - at_px);
    }
    let across = vec2<f32>(-along.y, along.x);
    let px = at_px + v.side * lines.width * across;
    // Pulled towards the eye by a fraction of its distance (Bevy's depth is the reciprocal of
    // the distance), never past the near plane (w).
    let depth = min(at.z * (1.0 + lines.depth_pull), at.w);
    return Fragment(vec4<f32>(px / half_size * at.w, depth, at.w), v.color);
}

@fragment
fn fragment(f: Fragment) -> @location(0) vec4<f32> {
    return f.color;
}
