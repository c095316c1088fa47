# If the brown stick were removed, which stick would pink fluid pass? | Cyan stick
# expected: yes

def execute_command(video):
    fluid_scene = SoftScene(video, 'fluid')
    pink_fluid = fluid_scene.find("pink fluid")
    cyan_stick = fluid_scene.find("cyan stick")

    # "If the brown stick were removed" is a counterfactual: remove it.
    cf_init_event = fluid_scene.register_event([], "remove", "brown stick")
    fluid_cf_scene = fluid_scene.init_dyn_simulation(cf_init_event)

    flag = fluid_cf_scene.happen(pink_fluid, "passing", cyan_stick)
    return bool_to_yesno(flag)
