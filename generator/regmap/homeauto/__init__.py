"""What the home-automation back ends (ESPHome, Home Assistant) share: the registers and commands a
`--select` picks (`selection`), the entity facts and YAML output computed from the model (`entities`),
and the target both declare the same way (`target`). Used by those two back ends only; no back end itself.
"""
