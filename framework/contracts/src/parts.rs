//! The renderer's parts: each lab's code by contract, in one store, put there by the contract
//! itself (Mitsuba 3's plugins, nori's one-line registration).
//!
//! A contract's code goes in with [`Parts::insert`], which asks the contract ([`Part`]) where
//! it goes: under its own type always, and under every extension point of the renderer it
//! serves — lab 02's two halves under `dyn Intersection` and `dyn Shading`, a material lab's
//! code as a [`SurfaceModel`](crate::surface::SurfaceModel) of the path tracer. The renderer
//! looks its parts up by type and by name; which labs a pipeline holds decides what it draws.

use std::any::{Any, TypeId, type_name};
use std::collections::BTreeMap;
use std::sync::Arc;

use crate::Trace;
use crate::surface::SurfaceModel;

/// A contract (`dyn Trait`) whose code the store holds. [`#[contract]`](crate::contract)
/// implements it for `dyn Trait`: the code under its own type. A contract that serves more
/// (`#[contract(register = path)]`) also has `path(code, parts)` called, which puts it under
/// the renderer's extension points with [`Parts::put`] and [`Parts::add_surface`].
pub trait Part: Trace + Send + Sync + 'static {
    /// Puts `code` into `parts` as this contract's code.
    fn register(code: Arc<Self>, parts: &mut Parts);
}

/// One contract's code in the store, with how to trace it.
#[derive(Clone)]
struct Entry {
    /// The contract [`Parts::insert`] was given, which put this entry in.
    origin: TypeId,
    /// An `Arc<S>` of the contract `S`.
    code: Arc<dyn Any + Send + Sync>,
    /// `code` with its every call noted while the pixel inspector records.
    traced: fn(&(dyn Any + Send + Sync)) -> Arc<dyn Any + Send + Sync>,
}

/// A surface model of the path tracer, by the name a scene's material gives.
#[derive(Clone)]
struct Surface {
    /// The contract [`Parts::insert`] was given, which put this entry in.
    origin: TypeId,
    /// The contract's code and its adapter, `(Arc<S>, fn(Arc<S>) -> Arc<dyn SurfaceModel>)`.
    code: Arc<dyn Any + Send + Sync>,
    /// Adapts that code (traced first when asked) as the surface model.
    adapt: fn(&(dyn Any + Send + Sync), bool) -> Arc<dyn SurfaceModel>,
    /// The adapted code.
    model: Arc<dyn SurfaceModel>,
}

/// Each lab's code by contract, and the path tracer's surface models by name.
#[derive(Clone)]
pub struct Parts {
    by_contract: BTreeMap<TypeId, Entry>,
    surfaces: BTreeMap<String, Surface>,
    /// The contract being inserted while its [`Part::register`] runs.
    inserting: TypeId,
}

impl Default for Parts {
    fn default() -> Self {
        Parts {
            by_contract: BTreeMap::new(),
            surfaces: BTreeMap::new(),
            inserting: TypeId::of::<()>(),
        }
    }
}

impl Parts {
    /// `code` as the code of the contract `S` and of every extension point `S` serves
    /// ([`Part::register`]); code there before under those types or names is replaced.
    pub fn insert<S: Part + ?Sized>(&mut self, code: Arc<S>) {
        let outer = std::mem::replace(&mut self.inserting, TypeId::of::<S>());
        S::register(code, self);
        self.inserting = outer;
    }

    /// The store without the contract `S`'s code: every entry its [`Self::insert`] put in.
    pub fn remove_part<S: ?Sized + 'static>(&mut self) {
        let origin = TypeId::of::<S>();
        self.by_contract.retain(|_, e| e.origin != origin);
        self.surfaces.retain(|_, s| s.origin != origin);
    }

    /// `code` under the type `S` alone: what [`Part::register`] does for each type it serves.
    pub fn put<S: Trace + ?Sized + Send + Sync + 'static>(&mut self, code: Arc<S>) {
        self.by_contract.insert(
            TypeId::of::<S>(),
            Entry {
                origin: self.inserting,
                code: Arc::new(code),
                traced: |code| Arc::new(S::trace(as_arc::<S>(code))),
            },
        );
    }

    /// The code under the type `S`, if any.
    pub fn get<S: ?Sized + Send + Sync + 'static>(&self) -> Option<Arc<S>> {
        let entry = self.by_contract.get(&TypeId::of::<S>())?;
        entry.code.downcast_ref::<Arc<S>>().cloned()
    }

    /// The store without code under the type `S`.
    pub fn remove<S: ?Sized + 'static>(&mut self) {
        self.by_contract.remove(&TypeId::of::<S>());
    }

    /// `code` of the contract `S` as the path tracer's surface model `name` (the `model` a
    /// scene's material names), adapted by `adapt`.
    pub fn add_surface<S: Trace + ?Sized + Send + Sync + 'static>(
        &mut self,
        name: &str,
        code: Arc<S>,
        adapt: fn(Arc<S>) -> Arc<dyn SurfaceModel>,
    ) {
        let model = adapt(code.clone());
        self.surfaces.insert(
            name.to_owned(),
            Surface {
                origin: self.inserting,
                code: Arc::new((code, adapt)),
                adapt: adapt_stored::<S>,
                model,
            },
        );
    }

    /// The surface model a material names, if some lab registered it.
    pub fn surface(&self, name: &str) -> Option<&Arc<dyn SurfaceModel>> {
        self.surfaces.get(name).map(|s| &s.model)
    }

    /// The names of the registered surface models.
    pub fn surface_names(&self) -> impl Iterator<Item = &str> {
        self.surfaces.keys().map(String::as_str)
    }

    /// This store with every code [traced](crate::Traced), surface models adapted from the
    /// traced code.
    pub fn traced(&self) -> Parts {
        let by_contract = self
            .by_contract
            .iter()
            .map(|(id, entry)| {
                let code = (entry.traced)(entry.code.as_ref());
                (*id, Entry { code, ..*entry })
            })
            .collect();
        let surfaces = self
            .surfaces
            .iter()
            .map(|(name, s)| {
                let model = (s.adapt)(s.code.as_ref(), true);
                (name.clone(), Surface { model, ..s.clone() })
            })
            .collect();
        Parts {
            by_contract,
            surfaces,
            inserting: self.inserting,
        }
    }
}

impl std::fmt::Debug for Parts {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Parts")
            .field("contracts", &self.by_contract.len())
            .field("surfaces", &self.surfaces.keys().collect::<Vec<_>>())
            .finish()
    }
}

/// The `Arc<S>` a store's entry holds.
fn as_arc<S: ?Sized + 'static>(code: &(dyn Any + Send + Sync)) -> &Arc<S> {
    code.downcast_ref::<Arc<S>>().unwrap_or_else(|| {
        panic!(
            "a store entry of {} holds another type's code",
            type_name::<S>()
        )
    })
}

/// The surface model of a stored `(code, adapter)` pair of the contract `S`, adapted from the
/// traced code when `traced`.
fn adapt_stored<S: Trace + ?Sized + Send + Sync + 'static>(
    stored: &(dyn Any + Send + Sync),
    traced: bool,
) -> Arc<dyn SurfaceModel> {
    type Stored<S> = (Arc<S>, fn(Arc<S>) -> Arc<dyn SurfaceModel>);
    let (code, adapt) = stored
        .downcast_ref::<Stored<S>>()
        .unwrap_or_else(|| panic!("a surface model of {} holds another type", type_name::<S>()));
    adapt(if traced { S::trace(code) } else { code.clone() })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lab03::Shadows;
    use crate::{Waiting, lab02};

    #[test]
    fn a_contract_is_found_under_its_type_and_lab_02_under_both_halves() {
        let mut parts = Parts::default();
        parts.insert::<dyn Shadows>(Arc::new(Waiting::<dyn Shadows>::new(3)));
        assert!(parts.get::<dyn Shadows>().is_some());
        assert!(parts.get::<dyn lab02::Shading>().is_none());
        parts.insert::<dyn lab02::Lab02>(Arc::new(Waiting::<dyn lab02::Lab02>::new(2)));
        assert!(parts.get::<dyn lab02::Lab02>().is_some());
        assert!(parts.get::<dyn lab02::Shading>().is_some());
        assert!(parts.get::<dyn lab02::Intersection>().is_some());
        parts.remove::<dyn lab02::Intersection>();
        assert!(parts.get::<dyn lab02::Intersection>().is_none());
        // Removing a contract removes what its insertion put in, and nothing else.
        let mut without = parts.clone();
        without.remove_part::<dyn lab02::Lab02>();
        assert!(without.get::<dyn lab02::Shading>().is_none());
        assert!(without.get::<dyn Shadows>().is_some());
        let traced = parts.traced();
        assert!(
            traced.get::<dyn Shadows>().is_some() && traced.get::<dyn lab02::Shading>().is_some()
        );
    }
}
