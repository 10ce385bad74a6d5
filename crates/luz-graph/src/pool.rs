//! Transient images pooled by description across frames and graphs.

use ash::vk;

use crate::resource::ImageDesc;

/// An image the pool holds: the raw handle and a view of all of it. Dropping it releases it, so
/// the pool only drops images unused for more generations than frames can be in flight.
pub trait PooledImage {
    /// The image.
    fn raw(&self) -> vk::Image;
    /// A view of every mip and layer.
    fn view(&self) -> vk::ImageView;
}

/// Makes the images of a [`TransientPool`] (luz allocates through its own allocator).
pub trait ImageFactory {
    /// The image type.
    type Image: PooledImage;
    /// The factory's error.
    type Error: std::error::Error + Send + Sync + 'static;
    /// Creates an image for the transient `name` (a debug name) with `desc`.
    fn create(&mut self, name: &str, desc: &ImageDesc) -> Result<Self::Image, Self::Error>;
}

struct Entry<I> {
    image: I,
    desc: ImageDesc,
    in_use: bool,
    last_generation: u64,
    /// The image's last use (stages, write accesses): the source scope of its next first use.
    last_scope: (vk::PipelineStageFlags2, vk::AccessFlags2),
}

/// How a transient was obtained.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Acquired {
    pub slot: usize,
    pub created: bool,
    pub previous_scope: (vk::PipelineStageFlags2, vk::AccessFlags2),
}

/// Transient images kept across frames (and across graphs: one pool can serve several graphs
/// executed one after another on the same queue), keyed by [`ImageDesc`].
///
/// Every [`crate::CompiledGraph::execute`] is one generation. Within it, a transient whose last
/// use is over frees its image for a later transient of the same description. Each image
/// remembers its last use, which becomes the source scope of its next first use (the layout is
/// `UNDEFINED`: transient contents are discarded). Images unused for more than
/// `max_unused_generations` generations are dropped, which must exceed the frames in flight.
pub struct TransientPool<F: ImageFactory> {
    entries: Vec<Entry<F::Image>>,
    generation: u64,
    max_unused: u64,
}

impl<F: ImageFactory> Default for TransientPool<F> {
    fn default() -> Self {
        Self::new()
    }
}

impl<F: ImageFactory> TransientPool<F> {
    /// An empty pool dropping images unused for 4 generations.
    pub fn new() -> Self {
        Self::with_max_unused(4)
    }

    /// An empty pool dropping images unused for `max_unused_generations` generations.
    pub fn with_max_unused(max_unused_generations: u64) -> Self {
        Self {
            entries: Vec::new(),
            generation: 0,
            max_unused: max_unused_generations,
        }
    }

    /// The number of pooled images.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether the pool holds no image.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The number of executions so far.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// The pooled images and their descriptions.
    pub fn images(&self) -> impl Iterator<Item = (&ImageDesc, &F::Image)> {
        self.entries.iter().map(|e| (&e.desc, &e.image))
    }

    /// Drops every pooled image (after a device wait idle, e.g. on resize).
    pub fn clear(&mut self) {
        self.entries.clear();
    }

    pub(crate) fn begin(&mut self) {
        self.generation += 1;
        for e in &mut self.entries {
            e.in_use = false;
        }
    }

    pub(crate) fn acquire(
        &mut self,
        factory: &mut F,
        name: &str,
        desc: &ImageDesc,
    ) -> Result<Acquired, F::Error> {
        let generation = self.generation;
        if let Some(slot) = self
            .entries
            .iter()
            .position(|e| !e.in_use && e.desc == *desc)
        {
            let e = &mut self.entries[slot];
            e.in_use = true;
            e.last_generation = generation;
            return Ok(Acquired {
                slot,
                created: false,
                previous_scope: e.last_scope,
            });
        }
        let image = factory.create(name, desc)?;
        self.entries.push(Entry {
            image,
            desc: *desc,
            in_use: true,
            last_generation: generation,
            last_scope: Default::default(),
        });
        Ok(Acquired {
            slot: self.entries.len() - 1,
            created: true,
            previous_scope: Default::default(),
        })
    }

    pub(crate) fn image(&self, slot: usize) -> &F::Image {
        &self.entries[slot].image
    }

    /// Ends a transient's use of `slot`; `scope` is its last use, `keep_previous` adds the
    /// image's older last use (parts of it were not used).
    pub(crate) fn release(
        &mut self,
        slot: usize,
        scope: (vk::PipelineStageFlags2, vk::AccessFlags2),
        keep_previous: bool,
    ) {
        let e = &mut self.entries[slot];
        e.in_use = false;
        if keep_previous {
            e.last_scope.0 |= scope.0;
            e.last_scope.1 |= scope.1;
        } else {
            e.last_scope = scope;
        }
    }

    /// After a failed execution: whatever was recorded may touch the images in use anyhow.
    pub(crate) fn poison_in_use(&mut self) {
        for e in self.entries.iter_mut().filter(|e| e.in_use) {
            e.in_use = false;
            e.last_scope = (
                vk::PipelineStageFlags2::ALL_COMMANDS,
                vk::AccessFlags2::MEMORY_WRITE,
            );
        }
    }

    /// Drops images unused for too long; returns how many.
    pub(crate) fn end(&mut self) -> usize {
        let (generation, max) = (self.generation, self.max_unused);
        let before = self.entries.len();
        self.entries
            .retain(|e| generation.saturating_sub(e.last_generation) < max);
        before - self.entries.len()
    }
}
