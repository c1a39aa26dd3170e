//! Light groups: the names of a scene's groups of emitters, whose light the render also
//! gives apart (`render::lightgroups`, the `lightgroup` AOVs).

/// The light group of lights, emitters and worlds that name none, once any names one.
pub const DEFAULT_LIGHTGROUP: &str = "default";

/// The light groups of a scene whose IR names the groups `given`: those, then
/// [`DEFAULT_LIGHTGROUP`] for the emitters in none (unless a group has that name); none
/// without groups. Every front end derives the group images from this.
pub fn light_group_names(given: &[String]) -> Vec<String> {
    let mut names = given.to_vec();
    if !names.is_empty() && !names.iter().any(|n| n == DEFAULT_LIGHTGROUP) {
        names.push(DEFAULT_LIGHTGROUP.to_string());
    }
    names
}
