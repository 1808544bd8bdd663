//! Layers' instances packed for the GPU, and per-layer work kept while a
//! layer stays the same: a node re-makes its recipe whenever one input
//! changes (one ball moves), but the layers that did not change are the same
//! `Arc`s, so their packing (a normal matrix per instance) and their bounds
//! are not computed again.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use super::{Draw, GpuInstance, InstanceInput, Layer};

/// Layers packed one after another: the GPU instances, the draws and each
/// layer's range of instances.
pub(crate) type Packed = (Vec<GpuInstance>, Vec<Draw>, Vec<(u32, u32)>);

/// One layer's GPU instances and draws, its draws' `first_instance` counted
/// from the layer's first instance.
pub(crate) struct PackedLayer {
    instances: Vec<GpuInstance>,
    draws: Vec<Draw>,
}

/// A layer's instances in order, one draw per batch (two where a batch mixes
/// one- and double-sided materials: its one-sided instances first).
pub(crate) fn pack_layer(layer: &Layer) -> PackedLayer {
    let mut instances = Vec::new();
    let mut draws = Vec::new();
    let world = layer.map_world();
    for batch in &layer.batches {
        // Culling is per draw: a batch whose instances mix one- and
        // double-sided materials is packed one-sided instances first and
        // drawn twice, so only the double-sided ones keep their back faces.
        let double_sided = |i: &InstanceInput| world.is_some_and(|w| w.double_sided(i.material_id));
        // Without surface maps nothing is double-sided: one pass.
        let sides: &[bool] = if world.is_some() {
            &[false, true]
        } else {
            &[false]
        };
        for &two_sided in sides {
            let first_instance = instances.len() as u32;
            for inst in batch
                .instances
                .iter()
                .filter(|i| double_sided(i) == two_sided)
            {
                instances.push(GpuInstance {
                    model: inst.transform.to_cols_array_2d(),
                    previous_model: inst.previous_transform.to_cols_array_2d(),
                    normal_matrix: crate::camera::safe_inverse(inst.transform)
                        .transpose()
                        .to_cols_array_2d(),
                    color: inst.color,
                    info: [
                        batch.mesh.first_index_word(),
                        batch.mesh.vertices.start,
                        inst.material_id,
                        inst.object_id,
                    ],
                });
            }
            let instance_count = instances.len() as u32 - first_instance;
            // An empty batch keeps its (empty) one-sided draw, as before.
            if instance_count == 0 && (two_sided || !batch.instances.is_empty()) {
                continue;
            }
            draws.push(Draw {
                index_count: batch.mesh.index_count(),
                first_instance,
                instance_count,
                procedural: batch.mesh.is_procedural(),
                two_sided,
                bounds: (!batch.mesh.is_procedural()).then_some(batch.mesh.bounds),
            });
        }
    }
    PackedLayer { instances, draws }
}

/// Where the packed layers lie one after another: the draws (their
/// `first_instance` counted from the first layer's), each layer's range of
/// instances, and the instance count.
fn lay_out<'p>(
    packed: impl IntoIterator<Item = &'p PackedLayer>,
) -> (Vec<Draw>, Vec<(u32, u32)>, u32) {
    let (mut draws, mut ranges, mut count) = (Vec::new(), Vec::new(), 0u32);
    for layer in packed {
        draws.extend(layer.draws.iter().map(|d| Draw {
            first_instance: count + d.first_instance,
            ..*d
        }));
        let first = count;
        count += layer.instances.len() as u32;
        ranges.push((first, count));
    }
    (draws, ranges, count)
}

/// The packed layers one after another.
fn concatenate<'p>(packed: impl IntoIterator<Item = &'p PackedLayer> + Clone) -> Packed {
    let (draws, ranges, count) = lay_out(packed.clone());
    // Sized once: a thousand instances are ~230 KB, which grown by doubling
    // were copied and allocated again several times a frame.
    let mut instances = Vec::with_capacity(count as usize);
    for layer in packed {
        instances.extend_from_slice(&layer.instances);
    }
    (instances, draws, ranges)
}

/// The GPU instances of `layers` in order (see [`pack_layer`]), the draws,
/// and each layer's range of instances.
pub(crate) fn pack_instances(layers: &[Arc<Layer>]) -> Packed {
    let packed: Vec<PackedLayer> = layers.iter().map(|l| pack_layer(l)).collect();
    concatenate(&packed)
}

/// Layers packed for a kept instance buffer, not concatenated: each layer's
/// instances apart, so a layer lying where it lay last frame is neither
/// copied nor compared ([`crate::Renderer::kept_init_parts`]).
pub(crate) struct KeptPacking {
    pub layers: Vec<Arc<PackedLayer>>,
    /// Per layer: the same packing at the same place as last time.
    pub unchanged: Vec<bool>,
    pub draws: Vec<Draw>,
    pub ranges: Vec<(u32, u32)>,
    pub count: u32,
    /// Layers packed anew (the others' packing was kept).
    pub made: u64,
}

impl KeptPacking {
    /// Each layer's instances as bytes, in order.
    pub(crate) fn parts(&self) -> Vec<&[u8]> {
        self.layers
            .iter()
            .map(|l| bytemuck::cast_slice(&l.instances))
            .collect()
    }
}

/// As [`pack_instances`], taking the packing of each layer that `memo` saw
/// last time from there, and telling which layers lie where they lay in
/// `placement`'s last call with the same packing.
pub(crate) fn pack_instances_kept(
    layers: &[Arc<Layer>],
    memo: &LayerMemo<PackedLayer>,
    placement: &Placement,
) -> KeptPacking {
    let (packed, made) = memo.get(layers, pack_layer);
    let (draws, ranges, count) = lay_out(packed.iter().map(Arc::as_ref));
    let unchanged = placement.place(&packed, &ranges);
    KeptPacking {
        layers: packed,
        unchanged,
        draws,
        ranges,
        count,
        made,
    }
}

/// Where each layer's packing was laid last time (by the first instance),
/// held so that an address is never mistaken for a new packing's.
#[derive(Default)]
pub(crate) struct Placement(Mutex<Vec<(u32, Arc<PackedLayer>)>>);

impl Placement {
    /// Per layer, whether the same packing lay at the same first instance
    /// last time; then this call's layout is remembered.
    pub(crate) fn place(&self, packed: &[Arc<PackedLayer>], ranges: &[(u32, u32)]) -> Vec<bool> {
        let mut last = self.0.lock().unwrap_or_else(|e| e.into_inner());
        let now: Vec<(u32, Arc<PackedLayer>)> = ranges
            .iter()
            .zip(packed)
            .map(|(&(first, _), p)| (first, p.clone()))
            .collect();
        let unchanged = now
            .iter()
            .enumerate()
            .map(|(i, (first, p))| {
                last.get(i)
                    .is_some_and(|(f, q)| f == first && Arc::ptr_eq(p, q))
            })
            .collect();
        *last = now;
        unchanged
    }
}

/// Something computed from a layer, kept while the layer is the same `Arc`
/// (layers are immutable once shared). Holds the layers of the last call
/// only, so a layer no longer drawn is let go, and holding them keeps a new
/// layer from ever being mistaken for an old one at the same address.
pub(crate) struct LayerMemo<T>(Mutex<HashMap<usize, Kept<T>>>);

/// A layer (held, so its address stays its own) and what was computed from it.
type Kept<T> = (Arc<Layer>, Arc<T>);

impl<T> Default for LayerMemo<T> {
    fn default() -> Self {
        LayerMemo(Mutex::new(HashMap::new()))
    }
}

impl<T> LayerMemo<T> {
    /// Per layer: last call's value where it is the same layer, else
    /// `make`'s; and how many were made.
    pub(crate) fn get(
        &self,
        layers: &[Arc<Layer>],
        make: impl Fn(&Layer) -> T,
    ) -> (Vec<Arc<T>>, u64) {
        let mut kept = self.0.lock().unwrap_or_else(|e| e.into_inner());
        let mut made = 0;
        let mut now = HashMap::with_capacity(layers.len());
        let values = layers
            .iter()
            .map(|layer| {
                let at = Arc::as_ptr(layer) as usize;
                let value = match kept.get(&at).or_else(|| now.get(&at)) {
                    Some((_, value)) => Arc::clone(value),
                    None => {
                        made += 1;
                        Arc::new(make(layer))
                    }
                };
                now.insert(at, (layer.clone(), value.clone()));
                value
            })
            .collect();
        *kept = now;
        (values, made)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn empty_layer() -> Arc<Layer> {
        Arc::new(Layer::new(None, Vec::new(), Default::default(), None).expect("valid layer"))
    }

    #[test]
    fn a_layer_seen_last_time_is_not_computed_again() {
        let memo = LayerMemo::<usize>::default();
        let (a, b, c) = (empty_layer(), empty_layer(), empty_layer());
        let calls = std::sync::atomic::AtomicUsize::new(0);
        let count = |_: &Layer| calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let (first, made) = memo.get(&[a.clone(), b.clone()], count);
        assert_eq!(made, 2);
        // `a` again (and twice), `c` new: only `c` is computed.
        let (second, made) = memo.get(&[a.clone(), c.clone(), a.clone()], count);
        assert_eq!(made, 1);
        assert_eq!(*second[0], *first[0]);
        assert_eq!(*second[2], *first[0]);
        // `b` was not in the last call: it was let go, and is computed anew.
        let (_, made) = memo.get(&[b], count);
        assert_eq!(made, 1);
        assert_eq!(calls.load(std::sync::atomic::Ordering::Relaxed), 4);
    }
}
