# Is the fluid density of the pink fluid greater than that of the yellow fluid?
# expected: yes

def execute_command(video):
    fluid_scene = SoftScene(video, 'fluid')
    pink_fluid = fluid_scene.find("pink fluid")
    yellow_fluid = fluid_scene.find("yellow fluid")

    # query_pair knows whether the video shows how the two fluids layer.
    pink_density, yellow_density = fluid_scene.query_pair('density', pink_fluid, yellow_fluid)

    if pink_density is not None and yellow_density is not None:
        return bool_to_yesno(pink_density > yellow_density)
    else:
        return "can not answer"
