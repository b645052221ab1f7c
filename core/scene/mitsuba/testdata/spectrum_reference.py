import mitsuba as mi
mi.set_variant('scalar_rgb')
def xml_bsdf(spec):
    s = mi.load_string('<bsdf version="3.0.0" type="diffuse"><spectrum name="reflectance" value="%s"/></bsdf>' % spec)
    return mi.traverse(s)['reflectance.value']
def xml_emitter(spec):
    s = mi.load_string('<emitter version="3.0.0" type="constant"><spectrum name="radiance" value="%s"/></emitter>' % spec)
    return mi.traverse(s)['radiance.value']
for spec in ['400:0.1, 500:0.5, 600:0.9, 700:0.3', '360:0.5, 830:0.5', '450:0.2 550:0.8 650:0.4']:
    print('reflectance', repr(spec), list(xml_bsdf(spec)))
    print('radiance', repr(spec), list(xml_emitter(spec)))
print('reflectance 0.5', list(xml_bsdf('0.5')) if hasattr(xml_bsdf('0.5'),'__len__') else xml_bsdf('0.5'))
print('radiance 0.5', list(xml_emitter('0.5')))
